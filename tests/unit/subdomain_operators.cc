// Subdomain operators of the brick benchmark (doc/formulation.md) for both Dirichlet treatments,
// structured and METIS decompositions, and every local solver backend:
//   ‖K_i R_i‖ ≤ 1e-12 ‖K_i‖ ‖R_i‖ (Frobenius norms), R_iᵀR_i = I,
//   ‖K_i K_i⁺ K_i v − K_i v‖ ≤ 1e-10 ‖K_i v‖ for random v,
//   and the kernel dimension: 0 for a subdomain anchored on the clamped face (primal), 6 else;
//   every cell listed once under its part (Body::cells_of_part), and every subdomain mesh made
//   of exactly the cells of its part.

#include <deal.II/base/mpi.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>

#include <feticontact/local_solvers/local_solver.h>
#include <feticontact/scene/body.h>
#include <feticontact/subdomain/subdomain.h>

#include "test_tools.h"

#include <random>

using namespace dealii;
using namespace FetiContact;

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize       mpi(argc, argv, 1);
  const FESystem<3>                      fe(FE_SimplexP<3>(1), 3);
  const MappingFE<3>                     mapping(FE_SimplexP<3>(1));
  std::mt19937                           random(42);
  std::uniform_real_distribution<double> uniform(-1, 1);

  const std::vector<std::pair<std::string, std::string>> decompositions = {
    {"3 blocks", "set Method = blocks\nset Blocks = 3, 1, 1"},
    {"METIS 8", "set Method = metis\nset Number of parts = 8"}};
  for (const auto &[name, decomposition] : decompositions)
    for (const bool primal : {true, false})
      {
        const auto scene = scene_from_text(brick_text(decomposition));
        Body       body(scene.bodies[0], 0);
        body.setup();
        // Body::cells_of_part lists every active cell once, under its own part (the subdomains
        // are built from these lists alone).
        std::size_t listed = 0;
        for (unsigned int p = 0; p < body.partition.n_parts; ++p)
          for (const auto &cell : body.cells_of_part[p])
            {
              ++listed;
              check(body.partition.part_of_cell[cell->active_cell_index()] == p,
                    name + ": a cell listed under part " + std::to_string(p) + " belongs to part " +
                      std::to_string(body.partition.part_of_cell[cell->active_cell_index()]));
            }
        check(listed == body.mesh.n_active_cells(),
              name + ": " + std::to_string(listed) + " cells listed by part, the mesh has " +
                std::to_string(body.mesh.n_active_cells()));
        for (const std::string backend : {"cholmod", "amesos2-klu2", "amesos-mumps", "umfpack"})
          for (unsigned int p = 0; p < body.partition.n_parts; ++p)
            {
              if (backend != "cholmod" && p > 1)
                continue; // other backends: two subdomains suffice
              Subdomain s(body, body.part_cells(p), p, primal, fe);
              check(s.mesh.n_active_cells() == body.cells_of_part[p].size(),
                    name + ", subdomain " + std::to_string(p) + ": " +
                      std::to_string(s.mesh.n_active_cells()) + " cells, its part has " +
                      std::to_string(body.cells_of_part[p].size()));
              s.assemble(mapping);
              s.factorize(backend);
              const std::string label = name + (primal ? ", primal" : ", TFETI") + ", subdomain " +
                                        std::to_string(p) + ", " + backend;

              bool touches_clamp = false;
              for (const auto &v : s.prescribed)
                touches_clamp |= v.has_value();
              const unsigned int expected_modes = (primal && touches_clamp) ? 0 : 6;
              check(s.R.n() == expected_modes,
                    label + ": kernel dimension " + std::to_string(s.R.n()) + " (expected " +
                      std::to_string(expected_modes) + ")");

              const double norm_K = s.K.frobenius_norm();
              double       KR2 = 0, R2 = 0, orth = 0;
              for (unsigned int j = 0; j < s.R.n(); ++j)
                {
                  Vector<double> r(s.R.m()), Kr(s.R.m());
                  for (unsigned int i = 0; i < s.R.m(); ++i)
                    r[i] = s.R(i, j);
                  s.K.vmult(Kr, r);
                  KR2 += Kr.norm_sqr();
                  R2 += r.norm_sqr();
                  for (unsigned int l = 0; l < s.R.n(); ++l)
                    {
                      double dot = 0;
                      for (unsigned int i = 0; i < s.R.m(); ++i)
                        dot += s.R(i, l) * r[i];
                      orth = std::max(orth, std::abs(dot - (l == j ? 1.0 : 0.0)));
                    }
                }
              if (s.R.n() > 0)
                {
                  const double ratio = std::sqrt(KR2) / (norm_K * std::sqrt(R2));
                  check(ratio <= 1e-12, label + ": ‖K R‖/(‖K‖‖R‖) = " + sci(ratio));
                  check(orth <= 1e-12, label + ": |RᵀR − I| = " + sci(orth));
                }

              Vector<double> v(s.K.m()), Kv(s.K.m()), x(s.K.m()), KxKv(s.K.m());
              for (auto &vi : v)
                vi = uniform(random);
              s.K.vmult(Kv, v);
              x = Kv;
              s.apply_generalized_inverse(x);
              s.K.vmult(KxKv, x);
              KxKv -= Kv;
              const double ratio = KxKv.l2_norm() / Kv.l2_norm();
              check(ratio <= 1e-10, label + ": ‖K K⁺ K v − K v‖/‖K v‖ = " + sci(ratio));
            }
      }
  std::cout << (n_failures == 0 ? "PASSED" : "FAILED") << std::endl;
  return n_failures;
}
