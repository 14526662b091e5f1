// The triangular solves with CHOLMOD's supernodal factor of a FETI subdomain: CHOLMOD's own
// (cholmod_solve2, CholmodSolver::solve_by_library) against the project's (SupernodalSolve,
// CholmodSolver::solve), on the regularized stiffness matrix of a floating subdomain of the
// brick (8 × 8 × 8 cubes of 5 tetrahedra, 2,187 unknowns; doc/formulation.md, "The brick
// benchmark"; steel in SI units), as every multiplication by F in the contact solver makes them.
//
//   triangular_solves [--cubes N] [--copies C] [--rounds R]
//
// C solvers factorize copies of the same matrix, so that their factors lie apart in memory as
// the subdomains' do (default 64: about 240 MB, far more than the caches). Each of the R rounds
// (default 21) solves one random right-hand side with every copy, by one method; the rounds
// alternate between the two methods, so that both see the same state of the machine. Prints the
// time of every round on stderr and one CSV line on stdout:
//   n_dofs,factor_entries,supernodes,library_median_s,project_median_s,ratio,max_relative_difference
// (times per solve, medians over the rounds of each method; ratio = library / project;
// max_relative_difference = the largest ‖x − x_lib‖/‖x_lib‖ of the solves compared).

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/lac/vector.h>

#include <feticontact/local_solvers/cholmod_solver.h>
#include <feticontact/scene/body.h>
#include <feticontact/scene/scene_parameters.h>
#include <feticontact/subdomain/subdomain.h>

#include "benchmark_tools.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <iostream>
#include <memory>
#include <random>
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
    std::cerr << "Usage: " << program << " [--cubes N] [--copies C] [--rounds R]\n"
              << "  N: cubes per edge of a subdomain (default 8: 3(N+1)^3 = 2187 unknowns)\n"
              << "  C: factorized copies of the matrix, solved in turn (default 64)\n"
              << "  R: rounds, alternating between the two solves (default 21)\n";
  }

  /** The brick 0 ≤ x ≤ 3 with 3N × N × N cubes in three blocks of N × N × N, clamped at x = 0. */
  Parameters::Scene
  brick_scene(const unsigned int n_cubes)
  {
    const std::string n    = std::to_string(n_cubes);
    const std::string text = "subsection Body 1\n"
                             " set Name = brick\n"
                             " subsection Mesh\n"
                             "  set Lower corner = 0, 0, 0\n"
                             "  set Upper corner = 3, 1, 1\n"
                             "  set Subdivisions = " +
                             std::to_string(3 * n_cubes) + ", " + n + ", " + n +
                             "\n"
                             " end\n"
                             " subsection Boundary conditions\n"
                             "  set Clamped boundaries = x = xmin\n"
                             "  set Tractions = z = zmax: 0, 0, -1e8\n"
                             " end\n"
                             " subsection Decomposition\n"
                             "  set Method = blocks\n"
                             "  set Blocks = 3, 1, 1\n"
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
    BenchmarkTools::parse_command_line(argc, argv, {"--cubes", "--copies", "--rounds"});
  if (line.help || !line.ok)
    {
      print_usage(argv[0]);
      return line.help ? 0 : 1;
    }
  const unsigned int n_cubes  = line.positive("--cubes", 8);
  const unsigned int n_copies = line.positive("--copies", 64);
  const unsigned int n_rounds = line.positive("--rounds", 21);
  if (n_cubes == 0 || n_copies == 0 || n_rounds == 0)
    {
      print_usage(argv[0]);
      return 1;
    }

  try
    {
      const auto scene = brick_scene(n_cubes);
      Body       body(scene.bodies[0], 0);
      body.setup();
      const FESystem<3>  fe(FE_SimplexP<3>(1), 3);
      const MappingFE<3> mapping(FE_SimplexP<3>(1));
      // The middle block floats: TFETI's regularized matrix, K with the rows and columns of the
      // kernel-fixing unknowns replaced by their diagonal.
      Subdomain subdomain(body, body.part_cells(1), 1, /*eliminate_prescribed=*/false, fe);
      subdomain.assemble(mapping);
      subdomain.factorize("cholmod");
      const SparseMatrix<double> A = subdomain.regularized_stiffness();

      std::vector<std::unique_ptr<CholmodSolver>> copies;
      for (unsigned int c = 0; c < n_copies; ++c)
        {
          copies.push_back(std::make_unique<CholmodSolver>(CholmodSolver::Solves::project));
          copies.back()->factorize(A);
        }
      const cholmod_factor &L = copies.front()->factor_of_library();

      std::mt19937                           random(1);
      std::uniform_real_distribution<double> uniform(-1, 1);
      Vector<double>                         b(A.m()), x(A.m()), x_library(A.m());
      std::vector<double>                    t_library, t_project;
      double                                 max_difference = 0;
      using clock                                           = std::chrono::steady_clock;
      for (unsigned int r = 0; r < n_rounds; ++r)
        {
          for (auto &v : b)
            v = uniform(random);
          const bool library = r % 2 == 0;
          const auto start   = clock::now();
          for (const auto &solver : copies)
            {
              x = b;
              library ? solver->solve_by_library(x) : solver->solve(x);
            }
          const double seconds =
            std::chrono::duration<double>(clock::now() - start).count() / n_copies;
          (library ? t_library : t_project).push_back(seconds);
          std::fprintf(stderr,
                       "# round %u, %s: %.3e s per solve\n",
                       r + 1,
                       library ? "CHOLMOD's solve" : "project's solve",
                       seconds);
          // The last copy's x against CHOLMOD's solve of the same right-hand side.
          x_library = b;
          copies.back()->solve_by_library(x_library);
          Vector<double> x_project(b);
          copies.back()->solve(x_project);
          x_project -= x_library;
          max_difference = std::max(max_difference, x_project.l2_norm() / x_library.l2_norm());
        }
      std::printf("%u,%zu,%zu,%.4e,%.4e,%.3f,%.2e\n",
                  A.m(),
                  static_cast<std::size_t>(L.xsize),
                  static_cast<std::size_t>(L.nsuper),
                  median(t_library),
                  median(t_project),
                  median(t_library) / median(t_project),
                  max_difference);
      std::fflush(stdout);
    }
  catch (const std::exception &e)
    {
      std::cerr << "Error: " << e.what() << std::endl;
      return 1;
    }
  return 0;
}
