// The dual mortar coupling of two triangulated surfaces (contact/mortar.h):
//  - matching meshes 0.25 apart: every slave node fully covered, M = D δ (one master node of weight
//    1), D_kk the lumped area, the weighted gap 0.25 D_kk;
//  - a unit square split 5 × 5 against 7 × 7 (rotated diagonals), the master 0.1 below, tilted
//    by a slope of 0.05: Σ_k D_kk = 1 (the area), Σ_j M_kj = D_kk per node, Σ_j M_kj y_j = D_kk x_k
//    for the linear functions x, y, z (the patch test's consistency), and the weighted gaps are
//    the exact distances along the normal;
//  - a slave square reaching past the master: the nodes outside are not covered, those across
//    its edge are weighted by φ_k (covered in part) with positive weights summing to 1;
//  - the master facing away: no segment, the pairs counted; the master farther than the search
//    distance: no segment; behind the slave by more than it: the distance reported.

#include <feticontact/contact/mortar.h>

#include "test_tools.h"

#include <cmath>
#include <functional>

using namespace dealii;
using namespace FetiContact;

namespace
{
  /**
   * The square [x0, x0 + size]² split n × n into triangles (both diagonals alternating with
   * @p flip) at height z(x, y), with the outward normal pointing along @p up (±1 in z).
   */
  Mortar::Surface
  square(const unsigned int                           n,
         const double                                 x0,
         const double                                 size,
         const std::function<double(double, double)> &z,
         const double                                 up,
         const bool                                   flip)
  {
    Mortar::Surface s;
    for (unsigned int j = 0; j <= n; ++j)
      for (unsigned int i = 0; i <= n; ++i)
        {
          const double x = x0 + size * i / n, y = x0 + size * j / n;
          s.points.emplace_back(x, y, z(x, y));
        }
    const auto at = [&](unsigned int i, unsigned int j) { return j * (n + 1) + i; };
    for (unsigned int j = 0; j < n; ++j)
      for (unsigned int i = 0; i < n; ++i)
        if (((i + j) % 2 == 0) != flip)
          {
            s.triangles.push_back({{at(i, j), at(i + 1, j), at(i + 1, j + 1)}});
            s.triangles.push_back({{at(i, j), at(i + 1, j + 1), at(i, j + 1)}});
          }
        else
          {
            s.triangles.push_back({{at(i, j), at(i + 1, j), at(i, j + 1)}});
            s.triangles.push_back({{at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)}});
          }
    Tensor<1, 3> outward;
    outward[2] = up;
    Mortar::compute_normals(s, std::vector<Tensor<1, 3>>(s.triangles.size(), outward));
    return s;
  }

  void
  matching()
  {
    const auto slave = square(
      4, 0, 1, [](double, double) { return 0.25; }, -1, false);
    const auto master = square(
      4, 0, 1, [](double, double) { return 0.0; }, 1, false);
    Mortar::Statistics statistics;
    const auto         c            = Mortar::couple(slave, master, 0.5, statistics);
    double             worst_weight = 0, worst_area = 0, worst_gap = 0;
    bool               all_dual = true;
    for (unsigned int k = 0; k < c.size(); ++k)
      {
        all_dual &= c[k].dual && c[k].covered > 0;
        for (const auto &[j, m] : c[k].M)
          worst_weight = std::max(worst_weight, std::abs(m / c[k].D - (j == k ? 1 : 0)));
        worst_area = std::max(worst_area, std::abs(c[k].D - c[k].area) / c[k].area);
        worst_gap  = std::max(worst_gap, std::abs(c[k].weighted_gap / c[k].D - 0.25));
      }
    check(all_dual, "matching meshes: every slave node covered and dual");
    check(worst_weight < 1e-13, "matching meshes: M = D δ (" + sci(worst_weight) + ")");
    check(worst_area < 1e-13, "matching meshes: D_kk = the lumped area (" + sci(worst_area) + ")");
    check(worst_gap < 1e-13,
          "matching meshes: weighted gap / D_kk = 0.25 (" + sci(worst_gap) + ")");
  }

  void
  non_matching()
  {
    const auto plane = [](double x, double y) { return -0.1 + 0.05 * x + 0.02 * y; };
    const auto slave = square(
      5, 0, 1, [](double, double) { return 0.0; }, -1, false);
    const auto         master = square(7, 0, 1, plane, 1, true);
    Mortar::Statistics statistics;
    const auto         c     = Mortar::couple(slave, master, 0.2, statistics);
    double             total = 0, worst_sum = 0, worst_linear = 0, worst_gap = 0;
    bool               all_dual = true;
    for (unsigned int k = 0; k < c.size(); ++k)
      {
        all_dual &= c[k].dual;
        total += c[k].D;
        double         sum = 0;
        Tensor<1, 3>   mean;
        const Point<3> x = slave.points[k];
        for (const auto &[j, m] : c[k].M)
          {
            sum += m;
            mean += m * master.points[j];
          }
        worst_sum = std::max(worst_sum, std::abs(sum - c[k].D) / c[k].D);
        // Σ_j M_kj y_j = ∫ψ_k y(x) over the slave: D_kk times the master point below x_k.
        const Point<3> below(x[0], x[1], plane(x[0], x[1]));
        worst_linear = std::max(worst_linear, (mean / c[k].D - below).norm());
        // The gap along the slave normal (0, 0, −1) to the plane, times its cosine with the normal.
        worst_gap =
          std::max(worst_gap, std::abs(c[k].weighted_gap / c[k].D - (0 - plane(x[0], x[1]))));
      }
    check(all_dual, "5 × 5 against 7 × 7: every slave node covered and dual");
    check(std::abs(total - 1) < 1e-13, "5 × 5 against 7 × 7: Σ D_kk = 1 (" + sci(total - 1) + ")");
    check(worst_sum < 1e-13, "5 × 5 against 7 × 7: Σ_j M_kj = D_kk (" + sci(worst_sum) + ")");
    check(worst_linear < 1e-13,
          "5 × 5 against 7 × 7: Σ_j M_kj y_j = D_kk y(x_k) (" + sci(worst_linear) + ")");
    check(worst_gap < 1e-13,
          "5 × 5 against 7 × 7: weighted gap / D_kk = the distance (" + sci(worst_gap) + ")");
  }

  void
  partly_covered()
  {
    // The slave [0.5, 1.5]² over the master [0, 1]².
    const auto slave = square(
      4, 0.5, 1, [](double, double) { return 0.0; }, -1, false);
    const auto master = square(
      6, 0, 1, [](double, double) { return -0.01; }, 1, false);
    Mortar::Statistics statistics;
    const auto         c         = Mortar::couple(slave, master, 0.1, statistics);
    unsigned int       n_outside = 0, n_partly = 0, n_dual = 0, wrong = 0;
    for (unsigned int k = 0; k < c.size(); ++k)
      {
        const Point<3> &x = slave.points[k];
        if (c[k].covered == 0)
          {
            ++n_outside;
            wrong += (x[0] < 1.2 && x[1] < 1.2) ? 1 : 0;
            continue;
          }
        if (c[k].dual)
          {
            ++n_dual;
            wrong += (x[0] >= 1 || x[1] >= 1) ? 1 : 0;
            continue;
          }
        ++n_partly;
        double sum = 0;
        for (const auto &[j, m] : c[k].M)
          {
            sum += m;
            wrong += m < 0 ? 1 : 0;
          }
        wrong += std::abs(sum - c[k].D) > 1e-13 * c[k].D ? 1 : 0;
        wrong += std::abs(c[k].D - c[k].covered) > 1e-13 * c[k].D ? 1 : 0;
      }
    // 5 × 5 slave nodes at 0.5, 0.75, 1, 1.25, 1.5 (supports ± 0.25): 4 dual (x, y ≤ 0.75), 5
    // across the edge (x or y = 1), 16 outside (x or y ≥ 1.25).
    check(n_dual == 4 && n_partly == 5 && n_outside == 16 && wrong == 0,
          "slave past the master: " + std::to_string(n_dual) + " dual, " +
            std::to_string(n_partly) + " partly covered (positive weights summing to D_kk), " +
            std::to_string(n_outside) + " outside; " + std::to_string(wrong) + " wrong");
  }

  void
  refused()
  {
    const auto slave = square(
      3, 0, 1, [](double, double) { return 0.0; }, -1, false);
    Mortar::Statistics s;
    Mortar::couple(slave,
                   square(
                     3, 0, 1, [](double, double) { return -0.01; }, -1, false),
                   0.1,
                   s);
    check(s.n_segments == 0 && s.n_facing_away > 0,
          "facing away: no segment, " + std::to_string(s.n_facing_away) + " pairs counted");
    Mortar::couple(slave,
                   square(
                     3, 0, 1, [](double, double) { return -0.3; }, 1, false),
                   0.1,
                   s);
    check(s.n_segments == 0, "beyond the search distance: no segment");
    Mortar::couple(slave,
                   square(
                     3, 0, 1, [](double, double) { return 0.3; }, 1, false),
                   0.1,
                   s);
    check(s.n_segments == 0 && std::abs(s.min_distance + 0.3) < 1e-12,
          "0.3 behind the slave: no segment, the distance " + sci(s.min_distance) + " reported");
  }
} // namespace

int
main()
{
  matching();
  non_matching();
  partly_covered();
  refused();
  return n_failures;
}
