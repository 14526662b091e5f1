#include <deal.II/base/bounding_box.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/numerics/rtree.h>

#include <feticontact/contact/mortar.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace FetiContact::Mortar
{
  using namespace dealii;

  void
  compute_normals(Surface &surface, const std::vector<Tensor<1, 3>> &outward)
  {
    surface.triangle_normals.resize(surface.triangles.size());
    surface.point_normals.assign(surface.points.size(), Tensor<1, 3>());
    for (unsigned int t = 0; t < surface.triangles.size(); ++t)
      {
        const auto  &v = surface.triangles[t];
        Tensor<1, 3> area_normal =
          0.5 * cross_product_3d(surface.points[v[1]] - surface.points[v[0]],
                                 surface.points[v[2]] - surface.points[v[0]]);
        if (area_normal * outward[t] < 0)
          area_normal = -area_normal;
        surface.triangle_normals[t] = area_normal / area_normal.norm();
        for (const unsigned int i : v)
          surface.point_normals[i] += area_normal;
      }
    for (auto &n : surface.point_normals)
      if (n.norm() > 0)
        n /= n.norm();
  }

  namespace
  {
    using Point2 = std::array<double, 2>;

    /** cos 30°: triangles whose normals differ by more lie on two sides of a fold. */
    const double cos_fold_angle = std::sqrt(3.) / 2;

    double
    cross2(const Point2 &a, const Point2 &b, const Point2 &c)
    {
      return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    }

    /** The barycentric coordinates of @p p in the triangle @p t. */
    std::array<double, 3>
    barycentric(const std::array<Point2, 3> &t, const Point2 &p)
    {
      const double area = cross2(t[0], t[1], t[2]);
      const double l1   = cross2(t[0], p, t[2]) / area;
      const double l2   = cross2(t[0], t[1], p) / area;
      return {{1 - l1 - l2, l1, l2}};
    }

    /**
     * The part of the convex polygon @p subject inside the counter-clockwise triangle @p clip
     * (Sutherland–Hodgman).
     */
    std::vector<Point2>
    clip_polygon(std::vector<Point2> subject, const std::array<Point2, 3> &clip)
    {
      for (unsigned int e = 0; e < 3 && !subject.empty(); ++e)
        {
          const Point2       &p = clip[e], &q = clip[(e + 1) % 3];
          std::vector<Point2> out;
          for (unsigned int i = 0; i < subject.size(); ++i)
            {
              const Point2 &a = subject[i], &b = subject[(i + 1) % subject.size()];
              const double  da = cross2(p, q, a), db = cross2(p, q, b);
              if (da >= 0)
                out.push_back(a);
              if ((da >= 0) != (db >= 0))
                {
                  const double s = da / (da - db);
                  out.push_back({{a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])}});
                }
            }
          subject = std::move(out);
        }
      return subject;
    }

    double
    polygon_area(const std::vector<Point2> &polygon)
    {
      double area = 0;
      for (unsigned int i = 1; i + 1 < polygon.size(); ++i)
        area += 0.5 * cross2(polygon[0], polygon[i], polygon[i + 1]);
      return area;
    }

    /** The integrals of one slave point, with ψ_k and with φ_k, before the choice between them. */
    struct Accumulator
    {
      double                                            covered = 0, gap_dual = 0, gap_nodal = 0;
      std::map<unsigned int, std::pair<double, double>> M; ///< j → (∫ψ_k φ_j, ∫φ_k φ_j)
    };

    /**
     * The normal and the lumped area ∫ φ_k of each slave point over the part of the slave
     * surface that its coupling belongs to (see fold_frames()).
     */
    struct NodeFrames
    {
      std::vector<Tensor<1, 3>> normal;
      std::vector<double>       area;
      /**
       * Per point, the covered triangles beyond its fold, whose segments are no part of its
       * integrals (sorted; empty almost everywhere).
       */
      std::vector<std::vector<unsigned int>> excluded;

      bool
      excludes(const unsigned int k, const unsigned int t) const
      {
        return !excluded.empty() && !excluded[k].empty() &&
               std::binary_search(excluded[k].begin(), excluded[k].end(), t);
      }
    };

    /**
     * The point normals and lumped areas of the whole slave surface, except at a fold, where the
     * surface turns by more than the fold angle within a point's star (a slave surface that runs
     * round the edge of its body):
     * - a point whose covered triangles (those with a segment) lie within the fold angle of their
     *   mean normal while some uncovered triangle does not: the surface beyond the fold (the side
     *   of a block whose bottom is in contact) is no part of the contact surface there;
     * - a point covered on both sides of the fold (a block in the corner of an L-shaped master):
     *   the side whose segments come nearest to the master keeps the point, and the segments of
     *   the covered triangles of the other side are left out of its integrals (excluded).
     * The point's normal is then the mean over its triangles within the fold angle of the side
     * that keeps it, and its area is theirs. Elsewhere, smooth surfaces included, nothing changes.
     * @p nearest: per slave triangle the smallest distance of its segments (+∞: uncovered).
     */
    NodeFrames
    fold_frames(const Surface             &slave,
                const std::vector<double> &nearest,
                const std::vector<double> &areas,
                bool                      &any_fold)
    {
      const auto covered = [&](const unsigned int t) {
        return nearest[t] < std::numeric_limits<double>::infinity();
      };
      NodeFrames frames{slave.point_normals, std::vector<double>(slave.points.size()), {}};
      std::vector<std::vector<unsigned int>> star(slave.points.size());
      for (unsigned int t = 0; t < slave.triangles.size(); ++t)
        for (const unsigned int i : slave.triangles[t])
          {
            star[i].push_back(t);
            frames.area[i] += areas[t] / 3;
          }
      frames.excluded.resize(slave.points.size());
      any_fold = false;
      for (unsigned int k = 0; k < star.size(); ++k)
        {
          Tensor<1, 3> covered_normal;
          for (const unsigned int t : star[k])
            if (covered(t))
              covered_normal += areas[t] * slave.triangle_normals[t];
          if (covered_normal.norm() == 0)
            continue;
          covered_normal /= covered_normal.norm();
          const auto within = [&](const unsigned int t, const Tensor<1, 3> &n) {
            return slave.triangle_normals[t] * n >= cos_fold_angle;
          };
          bool covered_within = true, folded = false;
          for (const unsigned int t : star[k])
            if (covered(t))
              covered_within &= within(t, covered_normal);
            else
              folded |= !within(t, covered_normal);
          if (covered_within && !folded)
            continue;
          Tensor<1, 3> side = covered_normal;
          if (!covered_within)
            {
              unsigned int nearest_triangle = star[k].front();
              for (const unsigned int t : star[k])
                if (nearest[t] < nearest[nearest_triangle])
                  nearest_triangle = t;
              side = slave.triangle_normals[nearest_triangle];
            }
          Tensor<1, 3> normal;
          double       area = 0;
          for (const unsigned int t : star[k])
            if (within(t, side))
              {
                normal += areas[t] * slave.triangle_normals[t];
                area += areas[t] / 3;
              }
            else if (covered(t))
              frames.excluded[k].push_back(t); // star[k] is increasing: excluded[k] is sorted
          frames.normal[k] = normal / normal.norm();
          frames.area[k]   = area;
          any_fold         = true;
        }
      return frames;
    }

    /** A slave triangle in the plane through its first vertex, with its frame. */
    struct SlaveFrame
    {
      Point<3>              origin;
      Tensor<1, 3>          e1, e2, normal;
      std::array<Point2, 3> vertices;

      Point2
      project(const Point<3> &x) const
      {
        return {{(x - origin) * e1, (x - origin) * e2}};
      }
    };

    SlaveFrame
    slave_frame(const Surface &slave, const unsigned int s)
    {
      const auto &v = slave.triangles[s];
      SlaveFrame  f;
      f.origin = slave.points[v[0]];
      f.normal = slave.triangle_normals[s];
      f.e1     = slave.points[v[1]] - f.origin;
      f.e1 /= f.e1.norm();
      f.e2 = cross_product_3d(f.normal, f.e1);
      for (unsigned int i = 0; i < 3; ++i)
        f.vertices[i] = f.project(slave.points[v[i]]);
      return f;
    }

    /** Integrates one segment: the polygon @p polygon of slave triangle @p s under master @p m. */
    void
    integrate_segment(const Surface               &slave,
                      const Surface               &master,
                      const unsigned int           s,
                      const unsigned int           m,
                      const SlaveFrame            &frame,
                      const std::array<Point2, 3> &master_2d,
                      const std::array<double, 3> &height,
                      const std::vector<Point2>   &polygon,
                      const NodeFrames            &nodes,
                      std::vector<Accumulator>    &accumulators)
    {
      static const QGaussSimplex<2> rule(3); // degree 5
      for (unsigned int p = 1; p + 1 < polygon.size(); ++p)
        {
          const Point2 &a = polygon[0], &b = polygon[p], &c = polygon[p + 1];
          const double  jacobian = cross2(a, b, c); // twice the area
          for (unsigned int q = 0; q < rule.size(); ++q)
            {
              const double xi = rule.point(q)[0], eta = rule.point(q)[1];
              const Point2 x{{a[0] + xi * (b[0] - a[0]) + eta * (c[0] - a[0]),
                              a[1] + xi * (b[1] - a[1]) + eta * (c[1] - a[1])}};
              const double JxW        = rule.weight(q) * jacobian;
              const auto   phi_slave  = barycentric(frame.vertices, x);
              const auto   phi_master = barycentric(master_2d, x);
              Tensor<1, 3> normal;
              double       h = 0;
              for (unsigned int i = 0; i < 3; ++i)
                {
                  normal += phi_slave[i] * nodes.normal[slave.triangles[s][i]];
                  h += phi_master[i] * height[i];
                }
              const double g = h * (frame.normal * normal) / normal.norm();
              for (unsigned int i = 0; i < 3; ++i)
                {
                  if (nodes.excludes(slave.triangles[s][i], s))
                    continue;
                  Accumulator &acc = accumulators[slave.triangles[s][i]];
                  const double phi = phi_slave[i], psi = 4 * phi - 1;
                  acc.covered += phi * JxW;
                  acc.gap_dual += psi * g * JxW;
                  acc.gap_nodal += phi * g * JxW;
                  for (unsigned int j = 0; j < 3; ++j)
                    {
                      auto &entry = acc.M[master.triangles[m][j]];
                      entry.first += psi * phi_master[j] * JxW;
                      entry.second += phi * phi_master[j] * JxW;
                    }
                }
            }
        }
    }

    /**
     * Slave triangle @p s against master triangle @p m: clips, checks and integrates. Returns
     * whether a segment was integrated, and lowers @p nearest to the segment's smallest distance
     * in front of the slave triangle. Without @p accumulators only the overlap is measured
     * (the search behind the slave triangle for a master surface deeper than the search
     * distance).
     */
    bool
    couple_pair(const Surface            &slave,
                const Surface            &master,
                const unsigned int        s,
                const unsigned int        m,
                const SlaveFrame         &frame,
                const double              search_distance,
                Statistics               &statistics,
                const NodeFrames         &nodes,
                std::vector<Accumulator> *accumulators,
                double                   *nearest = nullptr)
    {
      std::array<Point2, 3> master_2d;
      std::array<double, 3> height;
      for (unsigned int i = 0; i < 3; ++i)
        {
          const Point<3> &x = master.points[master.triangles[m][i]];
          master_2d[i]      = frame.project(x);
          height[i]         = (x - frame.origin) * frame.normal;
        }
      const double slave_area =
        0.5 * std::abs(cross2(frame.vertices[0], frame.vertices[1], frame.vertices[2]));
      const double master_area = 0.5 * cross2(master_2d[0], master_2d[1], master_2d[2]);
      // A master triangle seen edge-on from the slave plane covers nothing.
      if (std::abs(master_area) < 1e-12 * slave_area)
        return false;
      std::array<Point2, 3> clip = master_2d;
      if (master_area < 0)
        std::swap(clip[1], clip[2]);
      std::vector<Point2> subject(frame.vertices.begin(), frame.vertices.end());
      if (cross2(subject[0], subject[1], subject[2]) < 0)
        std::swap(subject[1], subject[2]);
      const std::vector<Point2> polygon = clip_polygon(subject, clip);
      if (polygon.size() < 3 || polygon_area(polygon) < 1e-12 * slave_area)
        return false;
      if (master.triangle_normals[m] * frame.normal >= 0)
        {
          statistics.n_facing_away += accumulators != nullptr ? 1 : 0;
          return false;
        }
      double lowest = std::numeric_limits<double>::max();
      Point2 lowest_at{};
      for (const Point2 &x : polygon)
        {
          const auto   phi = barycentric(master_2d, x);
          const double h   = phi[0] * height[0] + phi[1] * height[1] + phi[2] * height[2];
          if (h < lowest)
            {
              lowest    = h;
              lowest_at = x;
            }
        }
      if (lowest > search_distance)
        return false;
      if (lowest < statistics.min_distance)
        {
          statistics.min_distance = lowest;
          statistics.deepest_point =
            frame.origin + lowest_at[0] * frame.e1 + lowest_at[1] * frame.e2;
        }
      if (accumulators == nullptr)
        return false;
      ++statistics.n_segments;
      if (nearest != nullptr)
        *nearest = std::min(*nearest, lowest);
      integrate_segment(
        slave, master, s, m, frame, master_2d, height, polygon, nodes, *accumulators);
      return true;
    }

    /** The bounding box of @p points widened by @p margin. */
    BoundingBox<3>
    box_around(const std::vector<Point<3>> &points, const double margin)
    {
      BoundingBox<3> box(points);
      box.extend(margin);
      return box;
    }

    /** The choice between ψ_k and φ_k per node (see the namespace's documentation). */
    NodeCoupling
    finish_node(const Accumulator &acc, const double area)
    {
      NodeCoupling c;
      c.area    = area;
      c.covered = acc.covered;
      if (acc.covered <= 0)
        return c;
      c.dual            = acc.covered >= (1 - 1e-8) * area;
      c.weighted_gap    = c.dual ? acc.gap_dual : acc.gap_nodal;
      const double tiny = 1e-14 * area;
      for (const auto &[j, integrals] : acc.M)
        {
          const double m = c.dual ? integrals.first : integrals.second;
          c.D += m;
          if (std::abs(m) > tiny)
            c.M.emplace_back(j, m);
        }
      return c;
    }
  } // namespace

  std::vector<NodeCoupling>
  couple(const Surface &slave,
         const Surface &master,
         const double   search_distance,
         Statistics    &statistics,
         const Share   &share)
  {
    statistics = Statistics();
    std::vector<std::pair<BoundingBox<3>, unsigned int>> boxes;
    boxes.reserve(master.triangles.size());
    for (unsigned int m = 0; m < master.triangles.size(); ++m)
      {
        const auto &v = master.triangles[m];
        boxes.emplace_back(BoundingBox<3>(std::vector<Point<3>>{master.points[v[0]],
                                                                master.points[v[1]],
                                                                master.points[v[2]]}),
                           m);
      }
    const auto tree = pack_rtree(boxes);

    // How far behind a slave triangle a master surface that overlaps the slave body is looked
    // for: the size of both surfaces together.
    std::vector<Point<3>> all_points = slave.points;
    all_points.insert(all_points.end(), master.points.begin(), master.points.end());
    const double depth   = share.depth > 0 ? share.depth :
                                             BoundingBox<3>(all_points).side_length(0) +
                                             BoundingBox<3>(all_points).side_length(1) +
                                             BoundingBox<3>(all_points).side_length(2);
    const auto   counted = [&](const unsigned int s) {
      return share.counted.empty() || share.counted[s];
    };
    Statistics not_counted;
    // Candidates by master triangle: the sums over them do not depend on the R-tree's order,
    // which depends on the master triangles present (a share of a surface has fewer).
    const auto by_triangle = [](const std::pair<BoundingBox<3>, unsigned int> &a,
                                const std::pair<BoundingBox<3>, unsigned int> &b) {
      return a.second < b.second;
    };

    std::vector<Accumulator> accumulators(slave.points.size());
    NodeFrames               nodes{slave.point_normals, {}, {}};
    std::vector<double> nearest(slave.triangles.size(), std::numeric_limits<double>::infinity());
    std::vector<double> areas(slave.triangles.size());
    std::vector<std::pair<unsigned int, unsigned int>>   segments;
    std::vector<std::pair<BoundingBox<3>, unsigned int>> candidates;
    for (unsigned int s = 0; s < slave.triangles.size(); ++s)
      {
        const auto           &v     = slave.triangles[s];
        const SlaveFrame      frame = slave_frame(slave, s);
        std::vector<Point<3>> corners{slave.points[v[0]], slave.points[v[1]], slave.points[v[2]]};
        areas[s] = 0.5 * std::abs(cross2(frame.vertices[0], frame.vertices[1], frame.vertices[2]));
        Statistics &counts = counted(s) ? statistics : not_counted;
        candidates.clear();
        tree.query(boost::geometry::index::intersects(box_around(corners, search_distance)),
                   std::back_inserter(candidates));
        std::sort(candidates.begin(), candidates.end(), by_triangle);
        counts.n_candidate_pairs += candidates.size();
        for (const auto &candidate : candidates)
          if (couple_pair(slave,
                          master,
                          s,
                          candidate.second,
                          frame,
                          search_distance,
                          counts,
                          nodes,
                          &accumulators,
                          &nearest[s]))
            segments.emplace_back(s, candidate.second);
        if (nearest[s] < std::numeric_limits<double>::infinity() || !counted(s))
          continue;
        // Nothing within the search distance: a master surface deeper behind the triangle (inside
        // the slave body) would be an overlap of the bodies that the coupling cannot see.
        for (unsigned int i = 0; i < 3; ++i)
          corners.push_back(corners[i] - depth * frame.normal);
        const BoundingBox<3> behind = box_around(corners, search_distance);
        if (statistics.searched_behind)
          statistics.searched_behind->merge_with(behind);
        else
          statistics.searched_behind = behind;
        candidates.clear();
        tree.query(boost::geometry::index::intersects(behind), std::back_inserter(candidates));
        std::sort(candidates.begin(), candidates.end(), by_triangle);
        for (const auto &candidate : candidates)
          couple_pair(
            slave, master, s, candidate.second, frame, search_distance, statistics, nodes, nullptr);
      }

    // At a fold of the slave surface the segments are integrated again with the normals of the
    // side that keeps each point (the gap's cosine uses the interpolated nodal normal), without
    // the other side's segments.
    bool any_fold = false;
    nodes         = fold_frames(slave, nearest, areas, any_fold);
    if (any_fold)
      {
        accumulators.assign(slave.points.size(), Accumulator());
        Statistics again;
        for (const auto &[s, m] : segments)
          couple_pair(slave,
                      master,
                      s,
                      m,
                      slave_frame(slave, s),
                      search_distance,
                      again,
                      nodes,
                      &accumulators);
      }

    std::vector<NodeCoupling> couplings(slave.points.size());
    for (unsigned int k = 0; k < slave.points.size(); ++k)
      {
        couplings[k]        = finish_node(accumulators[k], nodes.area[k]);
        couplings[k].normal = nodes.normal[k];
      }
    return couplings;
  }
} // namespace FetiContact::Mortar
