#include <deal.II/base/exceptions.h>

#include <feticontact/qp/separable_set.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace FetiContact::QP
{
  using namespace dealii;

  namespace
  {
    constexpr double infinity = std::numeric_limits<double>::infinity();
    /** Relative distance to an interval end that counts as "at the end". */
    constexpr double interval_activity_tolerance = 1e-14;
    /** ‖x − c‖ ≥ r(1 − this) counts as "on the disc boundary". */
    constexpr double disc_activity_tolerance = 1e-12;
  } // namespace

  SeparableSet::SeparableSet(const unsigned int n)
    : kind(n, Kind::free)
    , lower(n, -infinity)
    , upper(n, infinity)
    , scale(n, 0.)
  {}

  unsigned int
  SeparableSet::size() const
  {
    return kind.size();
  }

  void
  SeparableSet::set_interval(const unsigned int i, const double l, const double u)
  {
    AssertThrow(i < size(), ExcIndexRange(i, 0, size()));
    AssertThrow(kind[i] != Kind::disc,
                ExcMessage("SeparableSet: component " + std::to_string(i) +
                           " belongs to a disc and cannot be an interval."));
    AssertThrow(!std::isnan(l) && !std::isnan(u) && l <= u && l < infinity && u > -infinity,
                ExcMessage("SeparableSet: bad interval [" + std::to_string(l) + ", " +
                           std::to_string(u) + "] for component " + std::to_string(i) + "."));
    lower[i]        = l;
    upper[i]        = u;
    const Kind now  = (l == -infinity && u == infinity) ? Kind::free : Kind::interval;
    const auto here = std::lower_bound(intervals.begin(), intervals.end(), i);
    if (now == Kind::interval && kind[i] != Kind::interval)
      intervals.insert(here, i);
    else if (now == Kind::free && kind[i] == Kind::interval)
      intervals.erase(here);
    kind[i]  = now;
    scale[i] = std::max(std::isfinite(l) ? std::abs(l) : 0., std::isfinite(u) ? std::abs(u) : 0.);
  }

  void
  SeparableSet::set_lower_bound(const unsigned int i, const double l)
  {
    set_interval(i, l, infinity);
  }

  unsigned int
  SeparableSet::add_disc(const unsigned int           i,
                         const unsigned int           j,
                         const std::array<double, 2> &centre,
                         const double                 radius)
  {
    AssertThrow(i < size() && j < size() && i != j,
                ExcMessage("SeparableSet: bad disc components (" + std::to_string(i) + ", " +
                           std::to_string(j) + ")."));
    AssertThrow(kind[i] == Kind::free && kind[j] == Kind::free,
                ExcMessage("SeparableSet: disc components (" + std::to_string(i) + ", " +
                           std::to_string(j) + ") already belong to a block."));
    AssertThrow(std::isfinite(centre[0]) && std::isfinite(centre[1]),
                ExcMessage("SeparableSet: disc centre not finite."));
    AssertThrow(radius >= 0 && !std::isnan(radius),
                ExcMessage("SeparableSet: disc radius must be ≥ 0 (+∞: the block is free)."));
    kind[i] = kind[j] = Kind::disc;
    discs.push_back(Disc{i, j, centre, radius});
    return discs.size() - 1;
  }

  void
  SeparableSet::set_disc_radius(const unsigned int k, const double radius)
  {
    AssertThrow(k < discs.size(), ExcIndexRange(k, 0, discs.size()));
    AssertThrow(radius >= 0 && !std::isnan(radius),
                ExcMessage("SeparableSet: disc radius must be ≥ 0 (+∞: the block is free)."));
    discs[k].radius = radius;
  }

  void
  SeparableSet::set_disc_centre(const unsigned int k, const double c1, const double c2)
  {
    AssertThrow(k < discs.size(), ExcIndexRange(k, 0, discs.size()));
    AssertThrow(std::isfinite(c1) && std::isfinite(c2),
                ExcMessage("SeparableSet: disc centre not finite."));
    discs[k].centre = {{c1, c2}};
  }

  unsigned int
  SeparableSet::n_discs() const
  {
    return discs.size();
  }

  std::array<unsigned int, 2>
  SeparableSet::disc_components(const unsigned int k) const
  {
    AssertThrow(k < discs.size(), ExcIndexRange(k, 0, discs.size()));
    return {{discs[k].i, discs[k].j}};
  }

  std::array<double, 2>
  SeparableSet::disc_centre(const unsigned int k) const
  {
    AssertThrow(k < discs.size(), ExcIndexRange(k, 0, discs.size()));
    return discs[k].centre;
  }

  double
  SeparableSet::disc_radius(const unsigned int k) const
  {
    AssertThrow(k < discs.size(), ExcIndexRange(k, 0, discs.size()));
    return discs[k].radius;
  }

  int
  SeparableSet::interval_state(const unsigned int i, const double v) const
  {
    const double l = lower[i], u = upper[i];
    const double tolerance = interval_activity_tolerance * scale[i];
    if (u - l <= 2 * tolerance) // fixed, or narrower than the resolution of "at an end"
      return 2;
    if (v <= l + tolerance)
      return -1;
    if (v >= u - tolerance)
      return 1;
    return 0;
  }

  template <typename VectorType>
  bool
  SeparableSet::disc_active(const Disc &d, const VectorType &x) const
  {
    if (d.radius == 0)
      return true;
    const double y1 = x.local_element(d.i) - d.centre[0], y2 = x.local_element(d.j) - d.centre[1];
    return std::hypot(y1, y2) >= d.radius * (1 - disc_activity_tolerance);
  }

  template <typename VectorType>
  void
  SeparableSet::project(VectorType &x) const
  {
    AssertDimension(x.locally_owned_size(), size());
    for (const unsigned int i : intervals)
      x.local_element(i) = std::min(std::max(x.local_element(i), lower[i]), upper[i]);
    for (const Disc &d : discs)
      {
        const double y1   = x.local_element(d.i) - d.centre[0],
                     y2   = x.local_element(d.j) - d.centre[1];
        const double norm = std::hypot(y1, y2);
        if (norm > d.radius)
          {
            // norm > r ≥ 0, so norm > 0.
            const double s       = d.radius / norm;
            x.local_element(d.i) = d.centre[0] + s * y1;
            x.local_element(d.j) = d.centre[1] + s * y2;
          }
      }
  }

  template <typename VectorType>
  void
  SeparableSet::free_gradient(const VectorType &x,
                              const VectorType &g,
                              VectorType       &phi,
                              const DiscMode    mode) const
  {
    AssertDimension(x.locally_owned_size(), size());
    AssertDimension(g.locally_owned_size(), size());
    phi = g; // the free components; intervals and discs below
    for (const unsigned int i : intervals)
      if (interval_state(i, x.local_element(i)) != 0)
        phi.local_element(i) = 0;
    for (const Disc &d : discs)
      {
        if (!disc_active(d, x))
          {
            phi.local_element(d.i) = g.local_element(d.i);
            phi.local_element(d.j) = g.local_element(d.j);
          }
        else if (mode == DiscMode::rotations && d.radius > 0)
          {
            const auto   nu        = outward_normal(d, x);
            const double gn        = g.local_element(d.i) * nu[0] + g.local_element(d.j) * nu[1];
            phi.local_element(d.i) = g.local_element(d.i) - gn * nu[0];
            phi.local_element(d.j) = g.local_element(d.j) - gn * nu[1];
          }
        else
          phi.local_element(d.i) = phi.local_element(d.j) = 0;
      }
  }

  template <typename VectorType>
  void
  SeparableSet::chopped_gradient(const VectorType &x,
                                 const VectorType &g,
                                 VectorType       &beta,
                                 const DiscMode    mode) const
  {
    AssertDimension(x.locally_owned_size(), size());
    AssertDimension(g.locally_owned_size(), size());
    beta.reinit(g); // zero on the free components; intervals and discs below
    for (const unsigned int i : intervals)
      switch (interval_state(i, x.local_element(i)))
        {
          case -1:
            beta.local_element(i) = std::min(g.local_element(i), 0.);
            break;
          case 1:
            beta.local_element(i) = std::max(g.local_element(i), 0.);
            break;
          default: // inside or fixed
            beta.local_element(i) = 0;
        }
    for (const Disc &d : discs)
      {
        beta.local_element(d.i) = beta.local_element(d.j) = 0;
        if (d.radius == 0 || !disc_active(d, x))
          continue;
        const auto   nu = outward_normal(d, x);
        const double gn = g.local_element(d.i) * nu[0] + g.local_element(d.j) * nu[1];
        if (mode == DiscMode::rotations)
          {
            beta.local_element(d.i) = std::max(gn, 0.) * nu[0];
            beta.local_element(d.j) = std::max(gn, 0.) * nu[1];
          }
        else
          {
            beta.local_element(d.i) = g.local_element(d.i) - std::min(gn, 0.) * nu[0];
            beta.local_element(d.j) = g.local_element(d.j) - std::min(gn, 0.) * nu[1];
          }
      }
  }

  template <typename VectorType>
  void
  SeparableSet::projected_gradient(const VectorType &x, const VectorType &g, VectorType &gP) const
  {
    VectorType beta;
    free_gradient(x, g, gP);
    chopped_gradient(x, g, beta);
    gP += beta;
  }

  template <typename VectorType>
  double
  SeparableSet::max_feasible_step(const VectorType &x,
                                  const VectorType &d,
                                  const DiscMode    mode) const
  {
    AssertDimension(x.locally_owned_size(), size());
    AssertDimension(d.locally_owned_size(), size());
    double alpha = infinity;
    for (const unsigned int i : intervals)
      if (d.local_element(i) != 0)
        {
          // x_i − α d_i stays in [l, u].
          const double a = d.local_element(i) > 0 ?
                             (x.local_element(i) - lower[i]) / d.local_element(i) :
                             (upper[i] - x.local_element(i)) / (-d.local_element(i));
          alpha          = std::min(alpha, std::max(a, 0.));
        }
    for (const Disc &disc : discs)
      {
        const double d1 = d.local_element(disc.i), d2 = d.local_element(disc.j);
        if (d1 == 0 && d2 == 0)
          continue;
        if (disc.radius == 0)
          {
            alpha = 0;
            break;
          }
        if (mode == DiscMode::rotations && disc_active(disc, x))
          continue;
        // ‖y − α d‖² = r²: α²‖d‖² − 2α y·d + ‖y‖² − r² = 0, the positive root.
        const double y1 = x.local_element(disc.i) - disc.centre[0],
                     y2 = x.local_element(disc.j) - disc.centre[1];
        const double dd = d1 * d1 + d2 * d2;
        const double yd = y1 * d1 + y2 * d2;
        const double ny = std::hypot(y1, y2);
        const double room = std::max((disc.radius - ny) * (disc.radius + ny), 0.); // r² − ‖y‖²
        const double root = std::sqrt(yd * yd + dd * room);
        // Stable form of (yd + root)/dd: when yd < 0 use room/(root − yd).
        const double a = yd >= 0 ? (yd + root) / dd : (root - yd > 0 ? room / (root - yd) : 0.);
        alpha          = std::min(alpha, std::max(a, 0.));
      }
    return Reductions<VectorType>::min(alpha, x);
  }

  template <typename VectorType>
  std::array<double, 2>
  SeparableSet::outward_normal(const Disc &d, const VectorType &x) const
  {
    const double y1 = x.local_element(d.i) - d.centre[0], y2 = x.local_element(d.j) - d.centre[1];
    const double norm = std::hypot(y1, y2); // ≥ r(1 − 1e-12) > 0 on an active disc with r > 0
    return {{y1 / norm, y2 / norm}};
  }

  template <typename VectorType>
  double
  SeparableSet::arc_curvature(const VectorType &x, const VectorType &g, const VectorType &d) const
  {
    typename Reductions<VectorType>::Sum curvature(x);
    for (const Disc &disc : discs)
      {
        if (disc.radius == 0 || (d.local_element(disc.i) == 0 && d.local_element(disc.j) == 0) ||
            !disc_active(disc, x))
          continue;
        const auto   nu = outward_normal(disc, x);
        const double sigma =
          std::max(-(g.local_element(disc.i) * nu[0] + g.local_element(disc.j) * nu[1]), 0.);
        const double dn = d.local_element(disc.i) * nu[0] + d.local_element(disc.j) * nu[1];
        const double t1 = d.local_element(disc.i) - dn * nu[0],
                     t2 = d.local_element(disc.j) - dn * nu[1];
        curvature.add(disc.i, sigma / disc.radius * (t1 * t1 + t2 * t2));
      }
    return curvature.result(x);
  }

  template <typename VectorType>
  void
  SeparableSet::add_arc_curvature(const VectorType &x,
                                  const VectorType &g,
                                  const VectorType &d,
                                  VectorType       &Hd) const
  {
    for (const Disc &disc : discs)
      {
        if (disc.radius == 0 || (d.local_element(disc.i) == 0 && d.local_element(disc.j) == 0) ||
            !disc_active(disc, x))
          continue;
        const auto   nu = outward_normal(disc, x);
        const double sigma =
          std::max(-(g.local_element(disc.i) * nu[0] + g.local_element(disc.j) * nu[1]), 0.);
        const double dn = d.local_element(disc.i) * nu[0] + d.local_element(disc.j) * nu[1];
        Hd.local_element(disc.i) += sigma / disc.radius * (d.local_element(disc.i) - dn * nu[0]);
        Hd.local_element(disc.j) += sigma / disc.radius * (d.local_element(disc.j) - dn * nu[1]);
      }
  }

  template <typename VectorType>
  void
  SeparableSet::remove_normal_parts(const VectorType &x, VectorType &v) const
  {
    for (const Disc &disc : discs)
      {
        if (disc.radius == 0 || (v.local_element(disc.i) == 0 && v.local_element(disc.j) == 0) ||
            !disc_active(disc, x))
          continue;
        const auto   nu = outward_normal(disc, x);
        const double vn = v.local_element(disc.i) * nu[0] + v.local_element(disc.j) * nu[1];
        v.local_element(disc.i) -= vn * nu[0];
        v.local_element(disc.j) -= vn * nu[1];
      }
  }

  template <typename VectorType>
  void
  SeparableSet::precondition_arcs(const VectorType &x,
                                  const VectorType &g,
                                  const double      a,
                                  VectorType       &v,
                                  const double      exponent) const
  {
    for (const Disc &disc : discs)
      {
        if (disc.radius == 0 || (v.local_element(disc.i) == 0 && v.local_element(disc.j) == 0) ||
            !disc_active(disc, x))
          continue;
        const auto   nu = outward_normal(disc, x);
        const double sigma =
          std::max(-(g.local_element(disc.i) * nu[0] + g.local_element(disc.j) * nu[1]), 0.);
        const double factor = 1 + sigma / (disc.radius * a);
        const double scale  = exponent == 1 ? 1 / factor : std::pow(factor, -exponent);
        v.local_element(disc.i) *= scale;
        v.local_element(disc.j) *= scale;
      }
  }

  template <typename VectorType>
  bool
  SeparableSet::moves_active_discs(const VectorType &x, const VectorType &v) const
  {
    bool moves = false;
    for (const Disc &disc : discs)
      if (disc.radius > 0 && (v.local_element(disc.i) != 0 || v.local_element(disc.j) != 0) &&
          disc_active(disc, x))
        {
          moves = true;
          break;
        }
    return Reductions<VectorType>::any(moves, x);
  }

  template <typename VectorType>
  bool
  SeparableSet::nonzero_on_discs(const VectorType &v) const
  {
    bool nonzero = false;
    for (const Disc &d : discs)
      if (v.local_element(d.i) != 0 || v.local_element(d.j) != 0)
        {
          nonzero = true;
          break;
        }
    return Reductions<VectorType>::any(nonzero, v);
  }

  template <typename VectorType>
  double
  SeparableSet::largest_violation(const VectorType &x) const
  {
    AssertDimension(x.locally_owned_size(), size());
    double violation = 0;
    for (const unsigned int i : intervals)
      violation =
        std::max({violation, lower[i] - x.local_element(i), x.local_element(i) - upper[i]});
    for (const Disc &d : discs)
      violation = std::max(violation,
                           std::hypot(x.local_element(d.i) - d.centre[0],
                                      x.local_element(d.j) - d.centre[1]) -
                             d.radius);
    return Reductions<VectorType>::max(violation, x);
  }

  template <typename VectorType>
  double
  SeparableSet::support(const VectorType &w, const double zero) const
  {
    AssertDimension(w.locally_owned_size(), size());
    const double                         infinity = std::numeric_limits<double>::infinity();
    const double                         small    = zero * linfty_norm(w);
    typename Reductions<VectorType>::Sum sup(w);
    bool                                 unbounded = false;
    for (unsigned int i = 0; i < size() && !unbounded; ++i)
      {
        if (kind[i] == Kind::disc || std::abs(w.local_element(i)) <= small)
          continue;
        const double end = w.local_element(i) > 0 ? upper[i] : lower[i]; // ±∞ for a free component
        unbounded        = !std::isfinite(end);
        if (!unbounded)
          sup.add(i, end * w.local_element(i));
      }
    for (unsigned int k = 0; k < discs.size() && !unbounded; ++k)
      {
        const Disc  &d = discs[k];
        const double a = std::abs(w.local_element(d.i)) <= small ? 0. : w.local_element(d.i);
        const double b = std::abs(w.local_element(d.j)) <= small ? 0. : w.local_element(d.j);
        if (a == 0 && b == 0)
          continue;
        unbounded = !std::isfinite(d.radius);
        if (!unbounded)
          sup.add(d.i, d.centre[0] * a + d.centre[1] * b + d.radius * std::hypot(a, b));
      }
    if (Reductions<VectorType>::any(unbounded, w))
      return infinity;
    return sup.result(w);
  }

  template <typename VectorType>
  bool
  SeparableSet::is_feasible(const VectorType &x, const double relative_tolerance) const
  {
    return largest_violation(x) <= relative_tolerance * linfty_norm(x);
  }
  // The instantiations for the two vector types of the QP layer.
#define FETICONTACT_INSTANTIATE_SEPARABLE_SET(V)                                                   \
  template void   SeparableSet::project(V &) const;                                                \
  template void   SeparableSet::free_gradient(const V &, const V &, V &, const DiscMode) const;    \
  template void   SeparableSet::chopped_gradient(const V &, const V &, V &, const DiscMode) const; \
  template void   SeparableSet::projected_gradient(const V &, const V &, V &) const;               \
  template double SeparableSet::max_feasible_step(const V &, const V &, const DiscMode) const;     \
  template double SeparableSet::arc_curvature(const V &, const V &, const V &) const;              \
  template void   SeparableSet::add_arc_curvature(const V &, const V &, const V &, V &) const;     \
  template void   SeparableSet::remove_normal_parts(const V &, V &) const;                         \
  template void   SeparableSet::precondition_arcs(                                                 \
    const V &, const V &, const double, V &, const double) const;                                \
  template bool   SeparableSet::moves_active_discs(const V &, const V &) const;                    \
  template bool   SeparableSet::nonzero_on_discs(const V &) const;                                 \
  template double SeparableSet::support(const V &, const double) const;                            \
  template double SeparableSet::largest_violation(const V &) const;                                \
  template bool   SeparableSet::is_feasible(const V &, const double) const;

  FETICONTACT_INSTANTIATE_SEPARABLE_SET(DistributedVector)
#undef FETICONTACT_INSTANTIATE_SEPARABLE_SET
} // namespace FetiContact::QP
