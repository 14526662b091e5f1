// The project's triangular solves with CHOLMOD's supernodal factor (SupernodalSolve, used by
// CholmodSolver::solve) against CHOLMOD's own (CholmodSolver::solve_by_library), on the same
// factor:
//   the stiffness matrices of the three subdomains of the brick with 8 × 8 × 8 cubes each (steel
//   in SI units; primal elimination, so the matrix of the subdomain at the clamp is SPD, and the
//   regularized matrices of the floating ones): ‖x − x_lib‖ ≤ 1e-10 ‖x_lib‖, ‖K x − b‖ ≤ 1e-10 ‖b‖
//   and no more than 10 times the residual of x_lib, for random b; the 1D Laplacian tridiag(−1, 2,
//   −1) of size 50, whose supernodes have one to a few columns: the solution of A x = A·(1, …, 1)
//   within 1e-12 of (1, …, 1); a second solve with the same right-hand side gives the same bits (no
//   state between solves).
// And the 64-bit solve of the undecomposed body (solve_by_long_cholmod, the monolithic
// verification): the same solution as the 32-bit factor to 1e-10 on the subdomains' matrices and
// to 1e-12 on the Laplacian; an indefinite matrix (one diagonal entry negated) is refused by both
// with InputError naming "not positive definite", not with a crash or a wrong solution.

#include <deal.II/base/mpi.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/local_solvers/cholmod_solver.h>
#include <feticontact/scene/body.h>
#include <feticontact/subdomain/subdomain.h>

#include "test_tools.h"

#include <functional>
#include <random>

using namespace dealii;
using namespace FetiContact;

namespace
{
  /** ‖A x − b‖ / ‖b‖. */
  double
  relative_residual(const SparseMatrix<double> &A, const Vector<double> &x, const Vector<double> &b)
  {
    Vector<double> r(b.size());
    A.vmult(r, x);
    r -= b;
    return r.l2_norm() / b.l2_norm();
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize       mpi(argc, argv, 1);
  const FESystem<3>                      fe(FE_SimplexP<3>(1), 3);
  const MappingFE<3>                     mapping(FE_SimplexP<3>(1));
  std::mt19937                           random(7);
  std::uniform_real_distribution<double> uniform(-1, 1);

  const auto scene = scene_from_text(brick_text("set Method = blocks\nset Blocks = 3, 1, 1", 8));
  Body       body(scene.bodies[0], 0);
  body.setup();
  for (const bool primal : {true, false})
    for (unsigned int p = 0; p < body.partition.n_parts; ++p)
      {
        Subdomain s(body, body.part_cells(p), p, primal, fe);
        s.assemble(mapping);
        // K itself (primal elimination, SPD at the clamp), or, for floating subdomains, K with the
        // rows and columns of the kernel-fixing unknowns replaced by their diagonal: the matrix
        // the subdomain's own solver factorizes.
        s.factorize("cholmod");
        const SparseMatrix<double> A = s.regularized_stiffness();
        CholmodSolver              solver(CholmodSolver::Solves::project);
        solver.factorize(A);

        Vector<double> b(A.m());
        for (auto &v : b)
          v = uniform(random);
        Vector<double> x(b), x_library(b), x_again(b);
        solver.solve(x);
        solver.solve_by_library(x_library);
        solver.solve(x_again);

        const std::string label = std::string(primal ? "primal" : "TFETI") + ", subdomain " +
                                  std::to_string(p) + " (" + std::to_string(A.m()) + " unknowns)";
        Vector<double> difference(x);
        difference -= x_library;
        const double relative_difference = difference.l2_norm() / x_library.l2_norm();
        check(relative_difference <= 1e-10,
              label + ": ‖x − x_lib‖/‖x_lib‖ = " + sci(relative_difference));
        const double residual         = relative_residual(A, x, b);
        const double residual_library = relative_residual(A, x_library, b);
        check(residual <= 1e-10 && residual <= 10 * residual_library,
              label + ": ‖A x − b‖/‖b‖ = " + sci(residual) +
                " (CHOLMOD's solve: " + sci(residual_library) + ")");
        difference = x_again;
        difference -= x;
        check(difference.linfty_norm() == 0, label + ": a second solve gives the same bits");

        Vector<double> x_long(b);
        solve_by_long_cholmod(A, x_long);
        x_long -= x_library;
        check(x_long.l2_norm() <= 1e-10 * x_library.l2_norm(),
              label + ": 64-bit solve against the 32-bit one: " +
                sci(x_long.l2_norm() / x_library.l2_norm()));
      }

  // tridiag(−1, 2, −1): every supernode is a chain of one-column nodes merged by CHOLMOD's
  // relaxed amalgamation, the smallest case of the kernels' loops.
  const unsigned int     n = 50;
  DynamicSparsityPattern dsp(n);
  for (unsigned int i = 0; i < n; ++i)
    for (unsigned int j = (i > 0 ? i - 1 : 0); j <= std::min(i + 1, n - 1); ++j)
      dsp.add(i, j);
  SparsityPattern sparsity;
  sparsity.copy_from(dsp);
  SparseMatrix<double> laplacian(sparsity);
  for (unsigned int i = 0; i < n; ++i)
    {
      laplacian.set(i, i, 2.);
      if (i > 0)
        laplacian.set(i, i - 1, -1.);
      if (i + 1 < n)
        laplacian.set(i, i + 1, -1.);
    }
  Vector<double> ones(n), b(n);
  ones = 1.;
  laplacian.vmult(b, ones);
  CholmodSolver solver(CholmodSolver::Solves::project);
  solver.factorize(laplacian);
  Vector<double> x(b), x_library(b);
  solver.solve(x);
  solver.solve_by_library(x_library);
  x -= ones;
  x_library -= ones;
  check(x.linfty_norm() <= 1e-12,
        "1D Laplacian, n = 50: max |x − 1| = " + sci(x.linfty_norm()) +
          " (CHOLMOD's solve: " + sci(x_library.linfty_norm()) + ")");

  Vector<double>              x_long(b);
  const LongCholmodStatistics statistics = solve_by_long_cholmod(laplacian, x_long);
  x_long -= ones;
  check(x_long.linfty_norm() <= 1e-12,
        "1D Laplacian, 64-bit solve: max |x − 1| = " + sci(x_long.linfty_norm()));
  // L of a tridiagonal matrix under a fill-reducing ordering: n diagonal entries and at most one
  // below each (a path graph has an ordering without fill).
  check(statistics.factor_entries >= n && statistics.factor_entries <= 2 * n - 1,
        "1D Laplacian: entries of L " +
          std::to_string(static_cast<long>(statistics.factor_entries)) + " (expected n … 2n − 1)");

  // An indefinite matrix: the 33rd leading minor is negative.
  laplacian.set(32, 32, -2.);
  const auto refuses = [&](const std::function<void()> &factorize, const std::string &what) {
    try
      {
        factorize();
        check(false, what + ": an indefinite matrix was factorized");
      }
    catch (const InputError &e)
      {
        check(std::string(e.what()).find("not positive definite") != std::string::npos,
              what + ": message '" + e.what() + "'");
      }
  };
  refuses([&]() { CholmodSolver(CholmodSolver::Solves::project).factorize(laplacian); },
          "CholmodSolver");
  refuses(
    [&]() {
      Vector<double> y(b);
      solve_by_long_cholmod(laplacian, y);
    },
    "solve_by_long_cholmod");
  return n_failures;
}
