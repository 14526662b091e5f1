// The FETI operators of the brick benchmark (doc/formulation.md), primal and TFETI, structured and
// METIS:
//  - B_E has orthonormal rows (B_E B_Eᵀ = I) and the expected number of rows;
//  - gluing rows vanish on a continuous field;
//  - F is symmetric and positive semidefinite, P is a projector onto ker G, Gλ₀ = e (to rounding:
//    1e-12 relative, a few thousand ε for a Cholesky solve with GGᵀ of order 50), also for the
//    particular solution from a subset of the columns (zero on the others);
//  - G x = RᵀBᵀx (1e-14 relative) with the rounding-level entries of R left out of G, which on
//    the structured blocks (TFETI) leaves at most 3 entries of G per entry of B;
//  - the orthonormalized G̃ = L⁻¹PG has G̃G̃ᵀ = I (to 1e-10: rounding amplified by cond(L)).

#include <deal.II/base/mpi.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>

#include <feticontact/feti/dual_problem.h>
#include <feticontact/feti/equality_constraints.h>
#include <feticontact/feti/local_dual_rows.h>

#include "test_tools.h"

#include <functional>
#include <map>
#include <random>
#include <tuple>

using namespace dealii;
using namespace FetiContact;

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize       mpi(argc, argv, 1);
  const FESystem<3>                      fe(FE_SimplexP<3>(1), 3);
  const MappingFE<3>                     mapping(FE_SimplexP<3>(1));
  std::mt19937                           random(7);
  std::uniform_real_distribution<double> uniform(-1, 1);

  for (const auto &[name, decomposition, expected_primal_rows] :
       std::vector<std::tuple<std::string, std::string, unsigned int>>{
         {"3 blocks", "set Method = blocks\nset Blocks = 3, 1, 1", 150},
         {"METIS 8", "set Method = metis\nset Number of parts = 8", 0}})
    for (const bool primal : {true, false})
      {
        const std::string                  label = name + (primal ? ", primal" : ", TFETI");
        const auto                         scene = scene_from_text(brick_text(decomposition));
        std::vector<std::unique_ptr<Body>> bodies;
        bodies.push_back(std::make_unique<Body>(scene.bodies[0], 0));
        bodies[0]->setup();
        const unsigned int                      n_sub = bodies[0]->partition.n_parts;
        std::vector<std::unique_ptr<Subdomain>> subdomains;
        std::vector<Subdomain *>                owned;
        std::vector<unsigned int>               mode_offset{0};
        for (unsigned int p = 0; p < n_sub; ++p)
          {
            subdomains.push_back(
              std::make_unique<Subdomain>(*bodies[0], bodies[0]->part_cells(p), p, primal, fe));
            owned.push_back(subdomains.back().get());
          }
        const DualRows rows = build_equality_rows(MPI_COMM_SELF, owned, !primal);

        // Row count: gluing rows Σ_v (p_v − 1) per free component, plus (TFETI) one row per
        // copy of a clamped component.
        std::vector<std::vector<unsigned int>> holders(bodies[0]->mesh.n_vertices());
        for (const auto &cell : bodies[0]->mesh.active_cell_iterators())
          for (const unsigned int v : cell->vertex_indices())
            {
              auto              &h = holders[cell->vertex_index(v)];
              const unsigned int p = bodies[0]->partition.part_of_cell[cell->active_cell_index()];
              if (std::find(h.begin(), h.end(), p) == h.end())
                h.push_back(p);
            }
        unsigned int expected = 0;
        for (unsigned int v = 0; v < holders.size(); ++v)
          {
            const bool clamped = bodies[0]->prescribed.count(v) > 0;
            if (!clamped && !holders[v].empty())
              expected += 3 * (holders[v].size() - 1);
            if (clamped && !primal)
              expected += 3 * holders[v].size();
          }
        check(rows.n_rows() == expected,
              label + ": " + std::to_string(rows.n_rows()) + " rows of B_E (expected " +
                std::to_string(expected) + ")");
        if (primal && expected_primal_rows > 0)
          check(rows.n_rows() == expected_primal_rows,
                label + ": the paper's brick has 2 interfaces × 25 nodes × 3 = 150 gluing rows");

        // B_E B_Eᵀ = I.
        const double deviation = deviation_from_orthonormal(rows);
        check(deviation < 1e-14, label + ": |B_E B_Eᵀ − I| = " + sci(deviation));

        // Gluing rows vanish on a continuous field u(vertex, component).
        double on_continuous = 0;
        for (unsigned int r = 0; r < rows.n_rows(); ++r)
          if (rows.row_start[r + 1] - rows.row_start[r] > 1)
            {
              double s = 0;
              for (unsigned int k = rows.row_start[r]; k < rows.row_start[r + 1]; ++k)
                s += rows.entries[k].value *
                     std::sin(1.0 + rows.entries[k].body_vertex + 7.0 * rows.entries[k].component);
              on_continuous = std::max(on_continuous, std::abs(s));
            }
        check(on_continuous < 1e-14,
              label + ": gluing rows on a continuous field: " + sci(on_continuous));

        // The dual problem.
        for (const auto &s : subdomains)
          {
            s->assemble(mapping);
            s->factorize("cholmod");
            mode_offset.push_back(mode_offset.back() + s->R.n());
          }
        DualProblem        dual(MPI_COMM_WORLD, owned, mode_offset, rows);
        const unsigned int m = dual.size();
        // The operators on vectors of all rows (one rank holds them all).
        const LocalDualRows local(dual);
        const auto          apply_F = [&](const Vector<double> &v, Vector<double> &w) {
          DualVector product;
          dual.apply_F(local.restrict(v), product);
          w = local.gather(product);
        };
        const auto project = [&](Vector<double> &v) {
          DualVector d = local.restrict(v);
          dual.coarse.project(d);
          v = local.gather(d);
        };
        const auto apply_G = [&](const Vector<double> &v, Vector<double> &w) {
          dual.coarse.apply_G(local.restrict(v), w);
        };
        const auto apply_G_orthonormal = [&](const Vector<double> &v, Vector<double> &w) {
          dual.coarse.apply_G_orthonormal(local.restrict(v), w);
        };
        const auto apply_Gt_orthonormal = [&](const Vector<double> &z, Vector<double> &w) {
          DualVector d = local.vector();
          dual.coarse.apply_Gt_orthonormal(z, d);
          w = local.gather(d);
        };
        const auto particular_solution = [&](const Vector<double>                        &e,
                                             const std::function<unsigned int(unsigned)> &tier) {
          DualVector d;
          dual.coarse.particular_solution(e, tier, d);
          return local.gather(d);
        };
        Vector<double> x(m), y(m), Fx(m), Fy(m);
        for (unsigned int i = 0; i < m; ++i)
          {
            x[i] = uniform(random);
            y[i] = uniform(random);
          }
        apply_F(x, Fx);
        apply_F(y, Fy);
        const double asym = std::abs(x * Fy - y * Fx) / (Fx.l2_norm() * y.l2_norm());
        check(asym < 1e-12, label + ": F symmetric, |xᵀFy − yᵀFx|/(‖Fx‖‖y‖) = " + sci(asym));
        check(x * Fx >= -1e-14 * Fx.l2_norm() * x.l2_norm(), label + ": xᵀFx ≥ 0");

        Vector<double> Px(x), PPx, GPx;
        project(Px);
        PPx = Px;
        project(PPx);
        PPx -= Px;
        check(PPx.l2_norm() <= 1e-13 * x.l2_norm(),
              label + ": ‖P²x − Px‖/‖x‖ = " + sci(PPx.l2_norm() / x.l2_norm()));
        apply_G(Px, GPx);
        Vector<double> Gx;
        apply_G(x, Gx);
        if (Gx.size() > 0)
          check(GPx.l2_norm() <= 1e-13 * Gx.l2_norm(),
                label + ": ‖G P x‖/‖G x‖ = " + sci(GPx.l2_norm() / Gx.l2_norm()));
        // G = RᵀBᵀ as stored (entries of R at its rounding level left out) against the product
        // with the full R: the same to rounding. On the blocks of the structured brick, each
        // subdomain symmetric about its centroid, a DoF of component c carries one translation
        // and two rotations, so G has at most 3 entries per entry of B (6 with every entry of
        // R stored).
        {
          std::map<unsigned int, unsigned int> local_vertex;
          Vector<double>                       RtBtx(dual.coarse.n_modes());
          for (unsigned int p = 0; p < n_sub; ++p)
            {
              const Subdomain &sd = *subdomains[p];
              if (sd.R.n() == 0)
                continue;
              local_vertex.clear();
              for (unsigned int v = 0; v < sd.body_vertex.size(); ++v)
                local_vertex[sd.body_vertex[v]] = v;
              Vector<double> Btx(sd.dof_handler.n_dofs());
              for (unsigned int r = 0; r < rows.n_rows(); ++r)
                for (unsigned int k = rows.row_start[r]; k < rows.row_start[r + 1]; ++k)
                  if (rows.entries[k].subdomain == p)
                    {
                      const auto &entry = rows.entries[k];
                      Btx[sd.vertex_dofs[local_vertex.at(entry.body_vertex)][entry.component]] +=
                        entry.value * x[r];
                    }
              for (unsigned int j = 0; j < sd.R.n(); ++j)
                for (unsigned int d = 0; d < sd.R.m(); ++d)
                  RtBtx[mode_offset[p] + j] += sd.R(d, j) * Btx[d];
            }
          Vector<double> Gx_stored;
          apply_G(x, Gx_stored);
          Gx_stored -= RtBtx;
          if (RtBtx.size() > 0)
            check(Gx_stored.l2_norm() <= 1e-14 * RtBtx.l2_norm(),
                  label + ": ‖Gx − RᵀBᵀx‖/‖RᵀBᵀx‖ = " + sci(Gx_stored.l2_norm() / RtBtx.l2_norm()));
          if (decomposition.find("blocks") != std::string::npos && !primal)
            check(dual.coarse.n_entries() <= 3 * rows.entries.size(),
                  label + ": nnz(G) = " + std::to_string(dual.coarse.n_entries()) +
                    ", at most 3 nnz(B) = " + std::to_string(3 * rows.entries.size()));
        }
        // Orthonormalized G̃ = L⁻¹PG: G̃G̃ᵀ = I and G̃ᵀ is its transpose.
        {
          const unsigned int k         = dual.coarse.n_modes();
          double             deviation = 0, transpose = 0;
          Vector<double>     z(k), Gtz, GGtz, w(m), Gw;
          for (unsigned int j = 0; j < k; ++j)
            {
              z    = 0;
              z[j] = 1;
              apply_Gt_orthonormal(z, Gtz);
              apply_G_orthonormal(Gtz, GGtz);
              GGtz -= z;
              deviation = std::max(deviation, GGtz.linfty_norm());
            }
          for (unsigned int i = 0; i < m; ++i)
            w[i] = uniform(random);
          for (unsigned int j = 0; j < k; ++j)
            z[j] = uniform(random);
          apply_G_orthonormal(w, Gw);
          apply_Gt_orthonormal(z, Gtz);
          if (k > 0)
            {
              transpose = std::abs(Gw * z - Gtz * w) / (Gw.l2_norm() * z.l2_norm());
              check(deviation < 1e-10, label + ": |G̃G̃ᵀ − I| = " + sci(deviation));
              check(transpose < 1e-13, label + ": (G̃w)ᵀz = wᵀ(G̃ᵀz), relative " + sci(transpose));
            }
        }
        DualVector least_norm = local.vector();
        dual.coarse.least_norm_solution(dual.e, least_norm);
        const Vector<double> lambda0 = local.gather(least_norm);
        Vector<double>       Gl;
        apply_G(lambda0, Gl);
        if (dual.e.size() > 0)
          {
            Gl -= dual.e;
            check(Gl.l2_norm() <= 1e-12 * dual.e.l2_norm(),
                  label + ": ‖Gλ₀ − e‖/‖e‖ = " + sci(Gl.l2_norm() / dual.e.l2_norm()));

            // particular_solution: with every tenth column of tier 1, the others (still
            // restraining every mode) carry λ₀ alone, and Gλ₀ = e holds.
            std::vector<unsigned int> tier(m);
            for (unsigned int i = 0; i < m; ++i)
              tier[i] = i % 10 == 0 ? 1 : 0;
            const auto lambda_tiered =
              particular_solution(dual.e, [&](const unsigned int c) { return tier[c]; });
            double on_tier_1 = 0;
            for (unsigned int i = 0; i < m; i += 10)
              on_tier_1 = std::max(on_tier_1, std::abs(lambda_tiered[i]));
            apply_G(lambda_tiered, Gl);
            Gl -= dual.e;
            check(on_tier_1 == 0, label + ": λ₀ from the tier-0 columns is zero on the others");
            check(Gl.l2_norm() <= 1e-12 * dual.e.l2_norm(),
                  label + ": tiered λ₀, ‖Gλ₀ − e‖/‖e‖ = " + sci(Gl.l2_norm() / dual.e.l2_norm()));
            // Columns that cannot restrain the modes alone (a single one) are passed over: then
            // λ₀ is the least-norm solution.
            std::vector<unsigned int> one(m, 1);
            one[0] = 0;
            const auto lambda_all =
              particular_solution(dual.e, [&](const unsigned int c) { return one[c]; });
            Vector<double> difference(lambda_all);
            difference -= lambda0;
            check(difference.l2_norm() <= 1e-14 * lambda0.l2_norm(),
                  label + ": one tier-0 column does not restrain: the least-norm λ₀");
          }
      }
  std::cout << (n_failures == 0 ? "PASSED" : "FAILED") << std::endl;
  return n_failures;
}
