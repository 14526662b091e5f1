// Projected conjugate gradients on a small equality-constrained QP with a known solution:
// min ½xᵀAx − bᵀx s.t. Gx = e, A = MᵀM/n + I SPD (n = 40, M random), G 4 × 40. The exact solution
// comes from the KKT system [A Gᵀ; G 0][x; μ] = [b; e]; PCG from x₀ = Gᵀ(GGᵀ)⁻¹e with P = I −
// Gᵀ(GGᵀ)⁻¹G must reach it to 1e-8 and keep Gx = e. Also: the same with a badly scaled A,
// preconditioned by its diagonal (P M P), and a problem with Pb = 0 (x₀ is the solution).
// The vectors of x's space are DistributedVector on one process (global index = local index),
// those of G's range (k numbers) dealii::Vector<double>.

#include <deal.II/base/mpi.h>
#include <deal.II/lac/full_matrix.h>

#include <feticontact/base/reproducible_partitioner.h>
#include <feticontact/qp/projected_cg.h>

#include "qp_test_problems.h"
#include "test_tools.h"

#include <cmath>
#include <random>

using namespace dealii;
using namespace FetiContact;
using QPTestProblems::multiply;
using QPTestProblems::multiply_transposed;

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  const unsigned int                     n = 40, k = 4;
  std::mt19937                           random(3);
  std::uniform_real_distribution<double> uniform(-1, 1);
  FullMatrix<double>                     M(n, n), A(n, n), G(k, n);
  for (unsigned int i = 0; i < n; ++i)
    for (unsigned int j = 0; j < n; ++j)
      M(i, j) = uniform(random);
  M.Tmmult(A, M); // A = MᵀM/n + I: SPD, condition number about 2
  A /= n;
  for (unsigned int i = 0; i < n; ++i)
    A(i, i) += 1;
  for (unsigned int i = 0; i < k; ++i)
    for (unsigned int j = 0; j < n; ++j)
      G(i, j) = uniform(random);
  DistributedVector b(n);
  Vector<double>    e(k);
  for (auto &v : b)
    v = uniform(random);
  for (auto &v : e)
    v = uniform(random);

  // The exact solution of min ½xᵀHx − bᵀx s.t. Gx = e from the KKT system.
  const auto kkt_solution = [&](const FullMatrix<double> &H) {
    FullMatrix<double> KKT(n + k, n + k);
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        KKT(i, j) = H(i, j);
    for (unsigned int i = 0; i < k; ++i)
      for (unsigned int j = 0; j < n; ++j)
        KKT(n + i, j) = KKT(j, n + i) = G(i, j);
    KKT.gauss_jordan();
    Vector<double> rhs(n + k), sol(n + k);
    for (unsigned int i = 0; i < n; ++i)
      rhs[i] = b[i];
    for (unsigned int i = 0; i < k; ++i)
      rhs[n + i] = e[i];
    KKT.vmult(sol, rhs);
    DistributedVector x(n);
    for (unsigned int i = 0; i < x.locally_owned_size(); ++i)
      x.local_element(i) = sol[i];
    return x;
  };
  const DistributedVector x_exact = kkt_solution(A);

  FullMatrix<double> GGt(k, k), GGt_inv(k, k);
  G.mTmult(GGt, G);
  GGt_inv.invert(GGt);
  const auto project = [&](DistributedVector &x) {
    Vector<double>    Gx(k), mu(k);
    DistributedVector Gtmu;
    Gtmu.reinit(x, true);
    multiply(G, x, Gx);
    GGt_inv.vmult(mu, Gx);
    multiply_transposed(G, mu, Gtmu);
    x -= Gtmu;
  };
  const auto apply_A = [&](const DistributedVector &x, DistributedVector &y) { multiply(A, x, y); };

  Vector<double>    mu(k);
  DistributedVector x(n);
  GGt_inv.vmult(mu, e);
  multiply_transposed(G, mu, x);
  const auto report = QP::ProjectedCG<DistributedVector>(
                        QP::ProjectedCG<DistributedVector>::AdditionalData{1e-12, 1000})
                        .solve(apply_A, project, b, x);
  check(report.converged, "converged in " + std::to_string(report.iterations) + " iterations");
  DistributedVector error(x);
  error -= x_exact;
  check(error.l2_norm() <= 1e-8 * x_exact.l2_norm(),
        "‖x − x*‖/‖x*‖ = " + sci(error.l2_norm() / x_exact.l2_norm()));
  Vector<double> Gx(k);
  multiply(G, x, Gx);
  Gx -= e;
  check(Gx.l2_norm() <= 1e-12 * e.l2_norm(), "‖Gx − e‖/‖e‖ = " + sci(Gx.l2_norm() / e.l2_norm()));
  check(report.iterations <= n, "at most n iterations (" + std::to_string(report.iterations) + ")");

  // Preconditioned (P M P with M = diag(A)⁻¹ on a badly scaled A = S A S): the same solution,
  // and in fewer iterations than without, since the scaling S makes A ill-conditioned and the
  // diagonal removes it.
  {
    FullMatrix<double> AS(A);
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        AS(i, j) *= std::pow(10., 2. * i / n) * std::pow(10., 2. * j / n);
    const DistributedVector xs_exact = kkt_solution(AS);
    const auto              apply_AS = [&](const DistributedVector &v, DistributedVector &w) {
      multiply(AS, v, w);
    };
    const auto jacobi = [&](const DistributedVector &v, DistributedVector &w) {
      w.reinit(v, true);
      for (unsigned int i = 0; i < v.locally_owned_size(); ++i)
        w.local_element(i) = v.local_element(i) / AS(i, i);
    };
    DistributedVector x_plain(n), x_pre(n);
    multiply_transposed(G, mu, x_plain);
    x_pre            = x_plain;
    const auto plain = QP::ProjectedCG<DistributedVector>().solve(apply_AS, project, b, x_plain);
    const auto pre =
      QP::ProjectedCG<DistributedVector>().solve(apply_AS, project, b, x_pre, {}, jacobi);
    DistributedVector ep(x_pre);
    ep -= xs_exact;
    check(pre.converged && ep.l2_norm() <= 1e-7 * xs_exact.l2_norm(),
          "preconditioned: ‖x − x*‖/‖x*‖ = " + sci(ep.l2_norm() / xs_exact.l2_norm()));
    Vector<double> Gxp(k);
    multiply(G, x_pre, Gxp);
    Gxp -= e;
    check(Gxp.l2_norm() <= 1e-12 * e.l2_norm(),
          "preconditioned keeps Gx = e: " + sci(Gxp.l2_norm() / e.l2_norm()));
    check(plain.converged && pre.iterations < plain.iterations,
          "preconditioned in fewer iterations: " + std::to_string(pre.iterations) + " against " +
            std::to_string(plain.iterations));
  }

  // b in range(Gᵀ): the solution of the projected problem is x₀ + the A-correction; with A = I
  // and b = Gᵀc the minimizer over Gx = e is x₀ itself.
  const FullMatrix<double> I{IdentityMatrix(n)};
  Vector<double>           c(k);
  DistributedVector        b2(n), x2(n);
  c[0] = 1;
  multiply_transposed(G, c, b2);
  x2 = 0;
  multiply_transposed(G, mu, x2);
  const DistributedVector x0(x2);
  const auto              report2 =
    QP::ProjectedCG<DistributedVector>(
      QP::ProjectedCG<DistributedVector>::AdditionalData{1e-12, 100})
      .solve([&](const DistributedVector &v, DistributedVector &w) { multiply(I, v, w); },
             project,
             b2,
             x2);
  DistributedVector d(x2);
  d -= x0;
  check(report2.converged && d.l2_norm() <= 1e-14 * x0.l2_norm(),
        "Pb = 0, A = I: stays at x₀ (‖x − x₀‖ = " + sci(d.l2_norm()) + ")");
  std::cout << (n_failures == 0 ? "PASSED" : "FAILED") << std::endl;
  return n_failures;
}
