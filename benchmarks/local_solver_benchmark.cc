// Times the local sparse direct solver backends (LocalSolver::create) on the P1 elasticity
// stiffness matrix of the unit cube (0,1)^3 with N×N×N cubes, each split into 6 tetrahedra,
// clamped at x = xmin, loaded by a traction on x = xmax, one subdomain, primal Dirichlet
// elimination (K is SPD, 3(N+1)^3 rows: eliminated DoFs keep a diagonal row).
//
//   local_solver_benchmark --backend NAME --cubes N --repeat R
//
// Each of the R repetitions creates a fresh solver object, times factorize(K) and one
// solve() of the load vector f. Prints the times of every repetition on stderr and one CSV
// line on stdout:
//   backend,n_dofs,nnz,factorize_median_s,solve_median_s,relative_residual
// (nnz: stored entries of the full symmetric pattern; relative_residual: ‖K x − f‖/‖f‖ of the
// last solve).

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/lac/vector.h>

#include <feticontact/local_solvers/local_solver.h>
#include <feticontact/scene/body.h>
#include <feticontact/scene/scene_parameters.h>
#include <feticontact/subdomain/subdomain.h>

#include "benchmark_tools.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

using namespace dealii;
using namespace FetiContact;
using BenchmarkTools::median;

namespace
{
  void
  print_usage(const char *program)
  {
    std::cerr << "Usage: " << program << " --backend NAME --cubes N --repeat R\n"
              << "  NAME: one of " << LocalSolver::available_backends() << "\n"
              << "  N:    cubes per edge of the unit cube (3(N+1)^3 DoFs), N >= 1\n"
              << "  R:    repetitions (fresh solver each time; medians are printed), R >= 1\n";
  }

  /** The unit cube with N^3 cubes (6 tetrahedra each), as a parameter file would give it. */
  Parameters::Scene
  unit_cube_scene(const unsigned int n_cubes)
  {
    const std::string n    = std::to_string(n_cubes);
    const std::string text = "subsection Body 1\n"
                             " set Name = cube\n"
                             " subsection Mesh\n"
                             "  set Lower corner = 0, 0, 0\n"
                             "  set Upper corner = 1, 1, 1\n"
                             "  set Subdivisions = " +
                             n + ", " + n + ", " + n +
                             "\n"
                             "  set Tetrahedra per cube = 6\n"
                             " end\n"
                             " subsection Boundary conditions\n"
                             "  set Clamped boundaries = x = xmin\n"
                             "  set Tractions = x = xmax: 0, 0, -1e8\n"
                             " end\n"
                             " subsection Decomposition\n"
                             "  set Method = blocks\n"
                             "  set Blocks = 1, 1, 1\n"
                             " end\n"
                             "end\n";
    return BenchmarkTools::scene_from_text(text);
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  const auto line =
    BenchmarkTools::parse_command_line(argc, argv, {"--backend", "--cubes", "--repeat"});
  if (line.help || !line.ok)
    {
      print_usage(argv[0]);
      return line.help ? 0 : 1;
    }
  const auto         backend_given = line.values.find("--backend");
  const std::string  backend = backend_given == line.values.end() ? "" : backend_given->second;
  const unsigned int n_cubes = line.positive("--cubes", 0);
  const unsigned int repeat  = line.positive("--repeat", 0);
  if ((line.values.count("--cubes") && n_cubes == 0) ||
      (line.values.count("--repeat") && repeat == 0))
    {
      print_usage(argv[0]);
      return 1;
    }
  if (backend.empty() || n_cubes == 0 || repeat == 0)
    {
      std::cerr << "Missing argument(s).\n";
      print_usage(argv[0]);
      return 1;
    }

  try
    {
      LocalSolver::create(backend); // rejects an unknown name before the assembly

      const auto scene = unit_cube_scene(n_cubes);
      Body       body(scene.bodies[0], 0);
      body.setup();
      const FESystem<3>  fe(FE_SimplexP<3>(1), 3);
      const MappingFE<3> mapping(FE_SimplexP<3>(1));
      Subdomain          subdomain(body, body.part_cells(0), 0, /*eliminate_prescribed=*/true, fe);
      subdomain.assemble(mapping);
      const SparseMatrix<double> &K = subdomain.K;
      const Vector<double>       &f = subdomain.f;

      using clock = std::chrono::steady_clock;
      std::vector<double> t_factorize, t_solve;
      double              relative_residual = 0;
      for (unsigned int r = 0; r < repeat; ++r)
        {
          auto           solver = LocalSolver::create(backend);
          Vector<double> x(f);

          const auto t0 = clock::now();
          solver->factorize(K);
          const auto t1 = clock::now();
          solver->solve(x);
          const auto t2 = clock::now();

          t_factorize.push_back(std::chrono::duration<double>(t1 - t0).count());
          t_solve.push_back(std::chrono::duration<double>(t2 - t1).count());

          Vector<double> residual(f.size());
          K.vmult(residual, x);
          residual -= f;
          relative_residual = residual.l2_norm() / f.l2_norm();
          std::fprintf(stderr,
                       "# %s n_dofs=%u repetition %u: factorize %.6f s, solve %.6f s, "
                       "relative residual %.3e\n",
                       backend.c_str(),
                       K.m(),
                       r + 1,
                       t_factorize.back(),
                       t_solve.back(),
                       relative_residual);
        }

      std::printf("%s,%u,%zu,%.6e,%.6e,%.3e\n",
                  backend.c_str(),
                  K.m(),
                  static_cast<std::size_t>(K.n_nonzero_elements()),
                  median(t_factorize),
                  median(t_solve),
                  relative_residual);
      std::fflush(stdout);
    }
  catch (const std::exception &e)
    {
      std::cerr << "Error: " << e.what() << std::endl;
      return 1;
    }
  return 0;
}
