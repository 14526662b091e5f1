#include <feticontact/base/input_parsing.h>
#include <feticontact/contact/rigid_obstacle.h>
#include <feticontact/postprocessing/hertz_comparison.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

namespace FetiContact
{
  using namespace dealii;

  double
  HertzResult::a_error() const
  {
    return std::abs(a - a_hertz) / a_hertz;
  }

  double
  HertzResult::p0_error() const
  {
    return std::abs(p0 - p0_hertz) / p0_hertz;
  }

  JsonObject
  HertzResult::json() const
  {
    return JsonObject()
      .set("P", P)
      .set("R", R)
      .set("E_star", E_star)
      .set("a_hertz", a_hertz)
      .set("p0_hertz", p0_hertz)
      .set("a", a)
      .set("p0", p0)
      .set("a_relative_error", a_error())
      .set("p0_relative_error", p0_error())
      .set("total_normal_force", total_normal_force)
      .set("nodes_across_a", nodes_across_a)
      .set("p0_touch_node", p0_touch_node)
      .set("fit_nodes", n_fit_nodes);
  }

  void
  HertzResult::print(std::ostream &out) const
  {
    out << "Hertz (P = " << P << " N, R = " << R << " m, E* = " << E_star << " Pa): a = " << a
        << " m against " << a_hertz << " (" << (a - a_hertz) / a_hertz * 100 << "%), p0 = " << p0
        << " Pa against " << p0_hertz << " (" << (p0 - p0_hertz) / p0_hertz * 100
        << "%), fitted to " << n_fit_nodes << " nodes (the touch node alone: p0 = " << p0_touch_node
        << " Pa), " << nodes_across_a << " nodes across a, total normal contact force "
        << total_normal_force << " N" << std::endl;
  }

  double
  hertz_radius(const Parameters::Scene &scene)
  {
    // The obstacle's radius (0: flat), or nothing where Hertz's point contact does not apply.
    const auto obstacle_radius = [](const Parameters::ContactZone &zone) {
      return zone.rigid() ? zone.obstacle->hertz_radius() : std::optional<double>(0.);
    };
    require(!scene.contact.zones.empty() && obstacle_radius(scene.contact.zones[0]),
            "Verification/Hertz: contact zone 1 must be a rigid plane, a rigid sphere or a body "
            "pair.");
    const auto  &zone     = scene.contact.zones[0];
    const auto  &body     = scene.bodies[zone.body];
    const bool   pair     = !zone.rigid();
    const double obstacle = *obstacle_radius(zone);
    const double R        = scene.verification.hertz.sphere_radius > 0 ?
                              scene.verification.hertz.sphere_radius :
                            obstacle > 0 ? obstacle :
                            body.mesh.spherical_bottom_radius > 0 || !pair ?
                                           body.mesh.spherical_bottom_radius :
                                           scene.bodies[zone.master_body].mesh.spherical_bottom_radius;
    require(R > 0,
            "Verification/Hertz: no sphere radius (set Verification/Hertz/Sphere radius, or give "
            "body '" +
              body.name + "' or its master body a Spherical bottom radius).");
    return R;
  }

  double
  hertz_modulus(const Parameters::Scene &scene)
  {
    const auto &zone       = scene.contact.zones[0];
    const auto  compliance = [&](const unsigned int b) {
      const auto &m = scene.bodies[b].material;
      return (1 - m.poissons_ratio * m.poissons_ratio) / m.youngs_modulus;
    };
    return 1 / (compliance(zone.body) + (zone.rigid() ? 0.0 : compliance(zone.master_body)));
  }

  namespace
  {
    /** A node of the fit: its squared distance from the axis, its pressure and its weight. */
    struct FitSample
    {
      double r2, p, weight;
    };

    /**
     * The weighted least-squares fit of p² = p0² − (p0²/a²) r² to @p samples (weights: the
     * nodes' areas): p0 and a, or nothing when the fitted p² does not fall with r² (fewer
     * than two distinct radii, or a pressure that grows outwards).
     */
    std::optional<std::pair<double, double>>
    fit_hertz_ellipse(const std::vector<FitSample> &samples)
    {
      // Normal equations of min Σ w (q − A + B s)², s = r², q = p², for (A, −B).
      double w = 0, ws = 0, wss = 0, wq = 0, wsq = 0;
      for (const FitSample &f : samples)
        {
          const double q = f.p * f.p;
          w += f.weight;
          ws += f.weight * f.r2;
          wss += f.weight * f.r2 * f.r2;
          wq += f.weight * q;
          wsq += f.weight * f.r2 * q;
        }
      const double determinant = w * wss - ws * ws;
      if (!(determinant > 1e-12 * w * wss))
        return std::nullopt;
      const double A = (wss * wq - ws * wsq) / determinant;
      const double B = -(w * wsq - ws * wq) / determinant;
      if (!(A > 0 && B > 0))
        return std::nullopt;
      return std::make_pair(std::sqrt(A), std::sqrt(A / B));
    }

    /**
     * The zone's nodes on the ray from the touch node @p centre along x projected on its tangent
     * plane, within @p a of it, the touch node excluded (for a quarter or half model: its
     * symmetry line); 0 where the mesh has no line of nodes there.
     */
    unsigned int
    nodes_on_ray(const std::vector<ContactNode>  &nodes,
                 const std::vector<unsigned int> &zone_nodes,
                 const unsigned int               centre,
                 const double                     a)
    {
      const Tensor<1, 3> &n   = nodes[centre].n;
      Tensor<1, 3>        dir = Tensor<1, 3>({1., 0., 0.}) - n[0] * n;
      if (dir.norm() <= 1e-6)
        return 0;
      dir /= dir.norm();
      const Tensor<1, 3> across = cross_product_3d(n, dir);
      unsigned int       count  = 0;
      for (const unsigned int k : zone_nodes)
        {
          const Tensor<1, 3> d = nodes[k].x - nodes[centre].x;
          if (std::abs(d * across) <= 1e-9 * a && d * dir > 1e-9 * a && d * dir <= a)
            ++count;
        }
      return count;
    }
  } // namespace

  HertzResult
  compare_with_hertz(const Parameters::Scene              &scene,
                     const std::vector<ContactNode>       &nodes,
                     const std::vector<ContactNodeResult> &results)
  {
    const auto &parameters = scene.verification.hertz;

    HertzResult h;
    h.R      = hertz_radius(scene);
    h.E_star = hertz_modulus(scene);

    // The nodes of zone 1 and their pressures.
    std::vector<unsigned int> zone_nodes;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      if (nodes[k].zone == 0)
        zone_nodes.push_back(k);
    require(!zone_nodes.empty(), "Verification/Hertz: contact zone 1 has no nodes.");
    const auto pressure = [&](const unsigned int k) {
      return results[k].lambda_N / nodes[k].pressure_area;
    };
    for (const unsigned int k : zone_nodes)
      h.total_normal_force += results[k].lambda_N;
    h.total_normal_force *= parameters.symmetry_factor;
    h.P = parameters.total_force > 0 ? parameters.total_force : h.total_normal_force;
    require(h.P > 0, "Verification/Hertz: the computed normal contact force is zero (no contact).");
    h.a_hertz  = std::cbrt(3 * h.P * h.R / (4 * h.E_star));
    h.p0_hertz = 3 * h.P / (2 * numbers::PI * h.a_hertz * h.a_hertz);

    // The touch point: the node with the smallest initial gap, on the sphere's axis.
    const unsigned int centre = *std::min_element(zone_nodes.begin(),
                                                  zone_nodes.end(),
                                                  [&](const unsigned int i, const unsigned int j) {
                                                    return nodes[i].gap < nodes[j].gap;
                                                  });
    h.p0_touch_node           = pressure(centre);
    double p_max              = 0;
    for (const unsigned int k : zone_nodes)
      p_max = std::max(p_max, pressure(k));
    require(p_max > 0, "Verification/Hertz: no node of contact zone 1 is in contact.");

    // The pressed nodes, their distances from the axis in its tangent plane and their areas.
    const Tensor<1, 3>    &n = nodes[centre].n;
    std::vector<FitSample> samples;
    for (const unsigned int k : zone_nodes)
      if (pressure(k) > 1e-6 * p_max)
        {
          Tensor<1, 3> d = nodes[k].x - nodes[centre].x;
          d -= (d * n) * n;
          samples.push_back({d.norm_square(), pressure(k), nodes[k].area});
        }
    h.n_fit_nodes  = samples.size();
    const auto fit = fit_hertz_ellipse(samples);
    require(fit.has_value(),
            "Verification/Hertz: the pressures of contact zone 1 do not fall outwards from the "
            "touch point (" +
              std::to_string(samples.size()) +
              " nodes in contact); p² = p0²(1 − r²/a²) cannot be fitted.");
    h.p0             = fit->first;
    h.a              = fit->second;
    h.nodes_across_a = nodes_on_ray(nodes, zone_nodes, centre, h.a);
    return h;
  }
} // namespace FetiContact
