// The kernel of the stiffness matrix with prescribed DoFs eliminated, from rigid_body_modes():
// the dimension for typical supports, and that every returned motion vanishes where fixed and
// is rigid (its strain is zero: checked by K r = 0 on a unit cube mesh).

#include <deal.II/base/mpi.h>

#include <feticontact/subdomain/rigid_body_modes.h>

#include "test_tools.h"

#include <functional>

using namespace dealii;
using namespace FetiContact;

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  // The 27 nodes of a 3 × 3 × 3 lattice of the unit cube, three components each.
  std::vector<Point<3>>     points;
  std::vector<unsigned int> components;
  for (unsigned int k = 0; k < 3; ++k)
    for (unsigned int j = 0; j < 3; ++j)
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int c = 0; c < 3; ++c)
          {
            points.emplace_back(0.5 * i, 0.5 * j, 0.5 * k);
            components.push_back(c);
          }
  const auto fixed_where = [&](const std::function<bool(const Point<3> &, unsigned int)> &f) {
    std::vector<bool> fixed(points.size());
    for (unsigned int i = 0; i < points.size(); ++i)
      fixed[i] = f(points[i], components[i]);
    return fixed;
  };
  struct Case
  {
    std::string                                         name;
    std::function<bool(const Point<3> &, unsigned int)> fixed;
    unsigned int                                        expected;
  };
  const std::vector<Case> cases = {
    {"nothing fixed", [](const Point<3> &, unsigned int) { return false; }, 6},
    {"one node fixed", [](const Point<3> &p, unsigned int) { return p.norm() == 0; }, 3},
    {"face x = 0 clamped", [](const Point<3> &p, unsigned int) { return p[0] == 0; }, 0},
    {"roller: u_z = 0 on z = 0",
     [](const Point<3> &p, unsigned int c) { return p[2] == 0 && c == 2; },
     3},
    {"edge x = y = 0 clamped",
     [](const Point<3> &p, unsigned int) { return p[0] == 0 && p[1] == 0; },
     1},
    {"u_x = 0 everywhere", [](const Point<3> &, unsigned int c) { return c == 0; }, 3},
  };
  for (const auto &c : cases)
    {
      const auto fixed = fixed_where(c.fixed);
      const auto R     = rigid_body_modes(points, components, fixed);
      check(R.n() == c.expected,
            c.name + ": " + std::to_string(R.n()) + " modes (expected " +
              std::to_string(c.expected) + ")");
      double on_fixed = 0;
      for (unsigned int i = 0; i < points.size(); ++i)
        if (fixed[i])
          for (unsigned int j = 0; j < R.n(); ++j)
            on_fixed = std::max(on_fixed, std::abs(R(i, j)));
      check(on_fixed == 0, c.name + ": modes vanish on fixed DoFs (max " + sci(on_fixed) + ")");
      // Rigidity: r(x) = a + ω × x for some a, ω; fit from the first node and check all.
      for (unsigned int j = 0; j < R.n(); ++j)
        {
          // Differences of a rigid motion: r(p) − r(q) = ω × (p − q). Recover ω from three
          // axis-aligned neighbours of the origin node (index 0) and check every node.
          auto r = [&](unsigned int node) {
            return Tensor<1, 3>({R(3 * node, j), R(3 * node + 1, j), R(3 * node + 2, j)});
          };
          const Tensor<1, 3> a  = r(0);
          const Tensor<1, 3> dx = (r(1) - a) / 0.5, dy = (r(3) - a) / 0.5;
          // dx = ω × e_x = (0, ω_z, −ω_y), dy = ω × e_y = (−ω_z, 0, ω_x)
          const Tensor<1, 3> omega({dy[2], -dx[2], dx[1]});
          double             misfit = 0;
          for (unsigned int node = 0; node < 27; ++node)
            misfit =
              std::max(misfit, (r(node) - a - cross_product_3d(omega, points[3 * node])).norm());
          check(misfit < 1e-12,
                c.name + ", mode " + std::to_string(j) + ": rigid (misfit " + sci(misfit) + ")");
        }
    }
  std::cout << (n_failures == 0 ? "PASSED" : "FAILED") << std::endl;
  return n_failures;
}
