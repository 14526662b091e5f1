// One monolithic direct solve of the linear elastic problem of a scene's first body: the P1
// stiffness K of the undecomposed mesh (prescribed DoFs eliminated, keeping a diagonal row) is
// assembled and factorized by CHOLMOD, and K u = f is solved once. Contact is ignored: this is
// the cost of a single linear solve of the same mesh, the yardstick beside which
// benchmarks/scaling.py puts the time of the Coulomb contact solve (issue: "against a linear
// solve"). The body must be held by its Dirichlet boundary (K symmetric positive definite).
//
//   monolithic_solve [--set PATH=VALUE]... FILE.prm
//
// The parameter file is read as feticontact reads it (the same --set overrides); its
// decomposition is ignored. Prints progress on stderr and one JSON line on stdout:
//   {"n": free DoFs, "assembly": s, "factorization": s, "solve": s, "peak_rss_mib": MiB,
//    "factor_entries": nnz(L), "relative_residual": ‖K u − f‖/‖f‖}
//
// CHOLMOD is called through its 64-bit-integer interface (solve_by_long_cholmod), not through
// the project's LocalSolver (32-bit, enough for subdomains): the factor of the brick at about 10⁶
// unknowns holds nearly 2³¹ entries and its supernodal storage more.

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

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <sys/resource.h>
#include <utility>
#include <vector>

using namespace dealii;
using namespace FetiContact;

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  std::vector<std::string> overrides;
  std::string              filename;
  for (int a = 1; a < argc; ++a)
    {
      const std::string arg = argv[a];
      if (arg == "--set" && a + 1 < argc)
        overrides.emplace_back(argv[++a]);
      else if (!arg.empty() && arg[0] != '-' && filename.empty())
        filename = arg;
      else
        {
          std::cerr << "Usage: " << argv[0] << " [--set PATH=VALUE]... FILE.prm\n";
          return arg == "--help" || arg == "-h" ? 0 : 1;
        }
    }
  if (filename.empty())
    {
      std::cerr << "Usage: " << argv[0] << " [--set PATH=VALUE]... FILE.prm\n";
      return 1;
    }

  try
    {
      ParameterHandler  prm;
      const auto        origins = Parameters::Scene::read_parameter_file(prm, filename, overrides);
      Parameters::Scene scene;
      scene.parse_parameters(prm, origins);

      // One part: the whole body is a single "subdomain" with its Dirichlet DoFs eliminated.
      auto body_parameters                  = scene.bodies[0];
      body_parameters.decomposition.method  = Parameters::Decomposition::Method::blocks;
      body_parameters.decomposition.blocks  = {{1, 1, 1}};
      body_parameters.decomposition.n_parts = 1;

      using clock   = std::chrono::steady_clock;
      const auto t0 = clock::now();
      Body       body(body_parameters, 0);
      body.setup();
      body.check_held();
      const FESystem<3>  fe(FE_SimplexP<3>(1), 3);
      const MappingFE<3> mapping(FE_SimplexP<3>(1));
      Subdomain          subdomain(body, body.part_cells(0), 0, /*eliminate_prescribed=*/true, fe);
      const auto         t1 = clock::now();
      subdomain.assemble(mapping);
      const auto t2 = clock::now();

      Vector<double>              u(subdomain.f);
      const LongCholmodStatistics cholmod = solve_by_long_cholmod(subdomain.K, u);

      Vector<double> residual(u.size());
      subdomain.K.vmult(residual, u);
      residual -= subdomain.f;
      const double relative_residual = residual.l2_norm() / subdomain.f.l2_norm();

      rusage usage{};
      getrusage(RUSAGE_SELF, &usage);
      const auto seconds = [](const auto a, const auto b) {
        return std::chrono::duration<double>(b - a).count();
      };
      std::fprintf(stderr,
                   "# %u free DoFs (%u rows): mesh and DoFs %.3f s, assembly %.3f s, "
                   "factorization %.3f s (%.3g entries in L), solve %.3f s, relative residual "
                   "%.2e\n",
                   body.n_free_dofs(),
                   subdomain.K.m(),
                   seconds(t0, t1),
                   seconds(t1, t2),
                   cholmod.factorization_seconds,
                   cholmod.factor_entries,
                   cholmod.solve_seconds,
                   relative_residual);
      std::printf("{\"n\": %u, \"assembly\": %.6e, \"factorization\": %.6e, \"solve\": %.6e, "
                  "\"peak_rss_mib\": %.1f, \"factor_entries\": %.6e, \"relative_residual\": "
                  "%.3e}\n",
                  body.n_free_dofs(),
                  seconds(t1, t2),
                  cholmod.factorization_seconds,
                  cholmod.solve_seconds,
                  usage.ru_maxrss / 1024.0,
                  cholmod.factor_entries,
                  relative_residual);
      return relative_residual < 1e-8 ? 0 : 1;
    }
  catch (const std::exception &e)
    {
      std::cerr << "Error: " << e.what() << std::endl;
      return 1;
    }
}
