// The contact rows N, T1, T2 at contact nodes on subdomain interfaces (FETI/Contact rows at
// interfaces), on the brick (k = 4) cut into 3 × 2 × 2 blocks, TFETI, pressed on a rigid plane
// 0.01 below it (so that the gaps d are not zero):
//  - averaged rows: σ_k² is the number p of glued copies of the node (1, 2 on interface edges,
//    4 where four blocks meet), and every value occurs;
//  - averaged rows with the gluing and Dirichlet rows: B Bᵀ = I (1e-14), Dostál's setting;
//  - rows on the lowest copy: B Bᵀ ≠ I, a contact row and a gluing row at an interface node have
//    the product 1/√2 (> 0.5) — the defect the averaged rows remove;
//  - on a continuous field u the averaged row gives σ_k times the lowest copy's row (1e-14), and
//    the right-hand sides are c_avg = σ_k c_low (the same constraint, scaled).
// With a second plane at y = ymin, the nodes of the edge where the planes meet (a keeper and a
// node whose friction acts through it):
//  - the rows of all nodes at one vertex are one set held together, by the lowest copy of the
//    vertex (its home subdomain);
//  - hold_contact_nodes() on a rank holding the vertices of even number keeps exactly their
//    nodes, in order, with their numbers and rows, and every keeper renumbered to a held node of
//    the same vertex.

#include <deal.II/base/mpi.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>

#include <feticontact/contact/contact_geometry.h>
#include <feticontact/contact/contact_rows.h>
#include <feticontact/feti/equality_constraints.h>
#include <feticontact/scene/decomposition.h>

#include "test_tools.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

using namespace dealii;
using namespace FetiContact;

namespace
{
  /** Row @p r of @p rows applied to the continuous field u(vertex, component). */
  double
  on_continuous_field(const DualRows &rows, const unsigned int r)
  {
    double s = 0;
    for (unsigned int k = rows.row_start[r]; k < rows.row_start[r + 1]; ++k)
      s += rows.entries[k].value *
           std::sin(1.0 + 0.37 * rows.entries[k].body_vertex + 7.0 * rows.entries[k].component);
    return s;
  }

  /** The brick in 3 × 2 × 2 blocks with the contact zones of @p contact (a Contact subsection). */
  struct Brick
  {
    Parameters::Scene                  scene;
    std::vector<std::unique_ptr<Body>> bodies;

    Brick(const std::string &contact, const unsigned int n_zones)
    {
      ParameterHandler prm;
      Parameters::Scene::declare_parameters(prm, 1, n_zones);
      prm.parse_input_from_string(brick_text("set Method = blocks\nset Blocks = 3, 2, 2") +
                                  contact);
      scene.parse_parameters(prm);
      bodies.push_back(std::make_unique<Body>(scene.bodies[0], 0));
      bodies[0]->setup();
    }
  };
} // namespace

namespace
{
  /** The checks of the nodes at the edge of two planes (see the top of the file). */
  void
  check_vertex_groups()
  {
    std::string zones = "subsection Contact\n set Number of zones = 2\n";
    for (const std::string axis : {"z", "y"})
      zones += " subsection Zone " + std::string(axis == "z" ? "1" : "2") +
               "\n"
               "  set Type                 = rigid plane\n"
               "  set Body                 = 1\n"
               "  set Surface              = " +
               axis + " = " + axis +
               "min\n"
               "  set Friction coefficient = 0.3\n"
               "  set Plane point          = 0, 0, 0\n"
               "  set Plane normal         = " +
               (axis == "z" ? "0, 0, 1" : "0, 1, 0") + "\n end\n";
    const Brick    brick(zones + "end\n", 2);
    const auto    &bodies = brick.bodies;
    const auto     nodes  = find_contact_nodes(bodies, brick.scene.contact);
    DualLayout     layout;
    const DualRows rows =
      build_contact_rows(nodes, {0, bodies[0]->partition.n_parts}, layout, 0, false);

    unsigned int n_followers = 0, n_split = 0;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      if (nodes[k].keeper)
        {
          ++n_followers;
          const unsigned int a = layout.normal_row[k], b = layout.normal_row[*nodes[k].keeper];
          bool               together = false;
          for (const auto &set : rows.held_together)
            together = together || (std::count(set.begin(), set.end(), a) == 1 &&
                                    std::count(set.begin(), set.end(), b) == 1);
          n_split += !together;
        }
    check(n_followers > 0 && n_split == 0,
          std::to_string(n_followers) + " nodes at the edge, each held together with its keeper");
    // Every node's rows are in one set, held by the lowest copy of its slave vertex.
    std::vector<unsigned int> held_by_of_row(layout.size(), numbers::invalid_unsigned_int);
    for (unsigned int i = 0; i < rows.held_together.size(); ++i)
      for (const unsigned int r : rows.held_together[i])
        held_by_of_row[r] = rows.held_by[i];
    unsigned int n_not_home = 0;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      n_not_home += held_by_of_row[layout.normal_row[k]] != nodes[k].copies.parts.front();
    check(rows.held_by.size() == rows.held_together.size() && n_not_home == 0,
          "every node's rows held by its home subdomain: " + std::to_string(n_not_home) + " not");

    const HeldContactNodes held   = hold_contact_nodes(nodes, layout, [&](const unsigned int k) {
      return nodes[k].vertex % 2 == 0;
    });
    unsigned int           n_even = 0, n_wrong = 0, n_held_followers = 0;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      if (nodes[k].vertex % 2 == 0)
        {
          const unsigned int n = n_even++;
          n_wrong += n >= held.nodes.size() || held.layout.node_number(n) != k ||
                     held.nodes[n].vertex != nodes[k].vertex ||
                     held.layout.tangential_row[n] != layout.tangential_row[k];
          if (n < held.nodes.size() && held.nodes[n].keeper)
            {
              ++n_held_followers;
              const unsigned int keeper = *held.nodes[n].keeper;
              n_wrong += keeper >= held.nodes.size() ||
                         held.nodes[keeper].vertex != nodes[k].vertex ||
                         held.layout.node_number(keeper) != *nodes[k].keeper;
            }
        }
    check(n_even == held.nodes.size() && n_wrong == 0 && n_held_followers > 0 &&
            held.layout.n_normal == layout.n_normal,
          "hold_contact_nodes: " + std::to_string(held.nodes.size()) + " of " +
            std::to_string(nodes.size()) + " nodes held, " + std::to_string(n_held_followers) +
            " keepers renumbered, " + std::to_string(n_wrong) + " wrong");
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  const Brick                     brick("subsection Contact\n"
                                        " set Number of zones = 1\n"
                                        " subsection Zone 1\n"
                                        "  set Type                 = rigid plane\n"
                                        "  set Body                 = 1\n"
                                        "  set Surface              = z = zmin\n"
                                        "  set Friction coefficient = 0.3\n"
                                        "  set Plane point          = 0, 0, -0.01\n"
                                        "  set Plane normal         = 0, 0, 1\n"
                                        " end\n"
                                        "end\n",
                    1);
  const auto                     &bodies = brick.bodies;
  const unsigned int              n_sub  = bodies[0]->partition.n_parts;
  const std::vector<unsigned int> first_subdomain{0, n_sub};
  const auto                      nodes = find_contact_nodes(bodies, brick.scene.contact);
  const auto                      parts = parts_of_vertices(bodies[0]->mesh, bodies[0]->partition);
  check(n_sub == 12 && !nodes.empty(),
        std::to_string(nodes.size()) + " contact nodes on " + std::to_string(n_sub) +
          " subdomains");

  DualLayout                              low_layout, avg_layout;
  const FESystem<3>                       fe(FE_SimplexP<3>(1), 3);
  std::vector<std::unique_ptr<Subdomain>> subdomains;
  std::vector<Subdomain *>                owned;
  for (unsigned int p = 0; p < n_sub; ++p)
    {
      subdomains.push_back(
        std::make_unique<Subdomain>(*bodies[0], bodies[0]->part_cells(p), p, false, fe));
      owned.push_back(subdomains.back().get());
    }
  const DualRows     equality  = build_equality_rows(MPI_COMM_SELF, owned, true);
  DualRows           low       = build_contact_rows(nodes, first_subdomain, low_layout, 0, false);
  DualRows           avg       = build_contact_rows(nodes, first_subdomain, avg_layout, 0, true);
  const unsigned int n_contact = avg.n_rows();
  check(low.n_rows() == n_contact && n_contact == 3 * nodes.size(),
        "N, T1, T2: " + std::to_string(n_contact) + " rows either way");

  // σ_k² = p, the number of copies, and all of 1, 2 and 4 occur.
  unsigned int                         n_wrong_scale = 0;
  std::map<unsigned int, unsigned int> n_with_copies;
  for (unsigned int k = 0; k < nodes.size(); ++k)
    {
      const unsigned int p     = parts[nodes[k].vertex].size();
      const double       sigma = avg_layout.scale_of_node(k);
      if (std::abs(sigma * sigma - p) > 1e-14 * p || low_layout.scale_of_node(k) != 1.0)
        ++n_wrong_scale;
      ++n_with_copies[p];
    }
  check(n_wrong_scale == 0,
        "σ_k² = number of copies for averaged rows, σ_k = 1 on the lowest copy");
  check(n_with_copies[1] > 0 && n_with_copies[2] > 0 && n_with_copies[4] > 0,
        "contact nodes with 1, 2, 4 copies: " + std::to_string(n_with_copies[1]) + ", " +
          std::to_string(n_with_copies[2]) + ", " + std::to_string(n_with_copies[4]));

  // B Bᵀ = I with averaged rows; not with rows on the lowest copy.
  low.append(equality);
  avg.append(equality);
  const double avg_deviation = deviation_from_orthonormal(avg);
  const double low_deviation = deviation_from_orthonormal(low);
  check(avg_deviation < 1e-14, "averaged contact rows: |B Bᵀ − I| = " + sci(avg_deviation));
  check(low_deviation > 0.5 && low_deviation < 1 / std::sqrt(2.0) + 1e-14,
        "contact rows on the lowest copy: |B Bᵀ − I| = " + sci(low_deviation) +
          " (1/√2 against a gluing row)");

  // The same constraints, scaled by σ_k: rows on a continuous field and right-hand sides.
  double row_mismatch = 0, rhs_mismatch = 0, rhs_size = 0;
  for (unsigned int k = 0; k < nodes.size(); ++k)
    {
      const double              sigma = avg_layout.scale_of_node(k);
      std::vector<unsigned int> rows_of_node{avg_layout.normal_row[k]};
      for (unsigned int j = 0; j < 2; ++j)
        rows_of_node.push_back(avg_layout.tangential_row[k] + j);
      for (const unsigned int r : rows_of_node)
        {
          row_mismatch =
            std::max(row_mismatch,
                     std::abs(on_continuous_field(avg, r) - sigma * on_continuous_field(low, r)));
          rhs_mismatch = std::max(rhs_mismatch, std::abs(avg.c[r] - sigma * low.c[r]));
          rhs_size     = std::max(rhs_size, std::abs(low.c[r]));
        }
    }
  check(avg_layout.normal_row == low_layout.normal_row &&
          avg_layout.tangential_row == low_layout.tangential_row,
        "the same row layout either way");
  check(row_mismatch < 1e-14,
        "averaged row = σ_k × lowest copy's row on a continuous field: " + sci(row_mismatch));
  check(rhs_size > 0 && rhs_mismatch <= 1e-14 * rhs_size,
        "c_avg = σ_k c_low: " + sci(rhs_mismatch) + " (largest gap " + sci(rhs_size) + ")");

  check_vertex_groups();
  return n_failures;
}
