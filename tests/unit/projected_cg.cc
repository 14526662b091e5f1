// Projected conjugate gradients on a small equality-constrained QP with a known solution:
// min ½xᵀAx − bᵀx s.t. Gx = e, A = MᵀM/n + I SPD (n = 40, M random), G 4 × 40. The exact solution
// comes from the KKT system [A Gᵀ; G 0][x; μ] = [b; e]; PCG from x₀ = Gᵀ(GGᵀ)⁻¹e with P = I −
// Gᵀ(GGᵀ)⁻¹G must reach it to 1e-8 and keep Gx = e. Also: the same with a badly scaled A,
// preconditioned by its diagonal (P M P), and a problem with Pb = 0 (x₀ is the solution).

#include <deal.II/lac/full_matrix.h>

#include <feticontact/qp/projected_cg.h>

#include "test_tools.h"

#include <cmath>
#include <random>

using namespace dealii;
using namespace FetiContact;

int
main()
{
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
  Vector<double> b(n), e(k);
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
    Vector<double> x(n);
    for (unsigned int i = 0; i < n; ++i)
      x[i] = sol[i];
    return x;
  };
  const Vector<double> x_exact = kkt_solution(A);

  FullMatrix<double> GGt(k, k), GGt_inv(k, k);
  G.mTmult(GGt, G);
  GGt_inv.invert(GGt);
  const auto project = [&](Vector<double> &x) {
    Vector<double> Gx(k), mu(k), Gtmu(n);
    G.vmult(Gx, x);
    GGt_inv.vmult(mu, Gx);
    G.Tvmult(Gtmu, mu);
    x -= Gtmu;
  };
  const auto apply_A = [&](const Vector<double> &x, Vector<double> &y) { A.vmult(y, x); };

  Vector<double> mu(k), x(n);
  GGt_inv.vmult(mu, e);
  G.Tvmult(x, mu);
  const auto report = QP::ProjectedCG<dealii::Vector<double>>(
                        QP::ProjectedCG<dealii::Vector<double>>::AdditionalData{1e-12, 1000})
                        .solve(apply_A, project, b, x);
  check(report.converged, "converged in " + std::to_string(report.iterations) + " iterations");
  Vector<double> error(x);
  error -= x_exact;
  check(error.l2_norm() <= 1e-8 * x_exact.l2_norm(),
        "‖x − x*‖/‖x*‖ = " + sci(error.l2_norm() / x_exact.l2_norm()));
  Vector<double> Gx(k);
  G.vmult(Gx, x);
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
    const Vector<double> xs_exact = kkt_solution(AS);
    const auto apply_AS = [&](const Vector<double> &v, Vector<double> &w) { AS.vmult(w, v); };
    const auto jacobi   = [&](const Vector<double> &v, Vector<double> &w) {
      w.reinit(n);
      for (unsigned int i = 0; i < n; ++i)
        w[i] = v[i] / AS(i, i);
    };
    Vector<double> x_plain(n), x_pre(n);
    G.Tvmult(x_plain, mu);
    x_pre = x_plain;
    const auto plain =
      QP::ProjectedCG<dealii::Vector<double>>().solve(apply_AS, project, b, x_plain);
    const auto pre =
      QP::ProjectedCG<dealii::Vector<double>>().solve(apply_AS, project, b, x_pre, {}, jacobi);
    Vector<double> ep(x_pre);
    ep -= xs_exact;
    check(pre.converged && ep.l2_norm() <= 1e-7 * xs_exact.l2_norm(),
          "preconditioned: ‖x − x*‖/‖x*‖ = " + sci(ep.l2_norm() / xs_exact.l2_norm()));
    Vector<double> Gxp(k);
    G.vmult(Gxp, x_pre);
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
  Vector<double>           c(k), b2(n), x2(n);
  c[0] = 1;
  G.Tvmult(b2, c);
  x2 = 0;
  G.Tvmult(x2, mu);
  const Vector<double> x0(x2);
  const auto           report2 =
    QP::ProjectedCG<dealii::Vector<double>>(
      QP::ProjectedCG<dealii::Vector<double>>::AdditionalData{1e-12, 100})
      .solve([&](const Vector<double> &v, Vector<double> &w) { I.vmult(w, v); }, project, b2, x2);
  Vector<double> d(x2);
  d -= x0;
  check(report2.converged && d.l2_norm() <= 1e-14 * x0.l2_norm(),
        "Pb = 0, A = I: stays at x₀ (‖x − x₀‖ = " + sci(d.l2_norm()) + ")");
  std::cout << (n_failures == 0 ? "PASSED" : "FAILED") << std::endl;
  return n_failures;
}
