#include <feticontact/base/input_parsing.h>
#include <feticontact/postprocessing/hertz_comparison.h>

#include <algorithm>
#include <cmath>

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
      .set("nodes_across_a", nodes_across_a);
  }

  void
  HertzResult::print(std::ostream &out) const
  {
    out << "Hertz (P = " << P << " N, R = " << R << " m, E* = " << E_star << " Pa): a = " << a
        << " m against " << a_hertz << " (" << (a - a_hertz) / a_hertz * 100 << "%), p0 = " << p0
        << " Pa against " << p0_hertz << " (" << (p0 - p0_hertz) / p0_hertz * 100 << "%), "
        << nodes_across_a << " nodes across a, total normal contact force " << total_normal_force
        << " N" << std::endl;
  }

  double
  hertz_radius(const Parameters::Scene &scene)
  {
    require(!scene.contact.zones.empty() &&
              scene.contact.zones[0].type != Parameters::ContactZone::Type::rigid_cylinder,
            "Verification/Hertz: contact zone 1 must be a rigid plane, a rigid sphere or a body "
            "pair.");
    const auto  &zone = scene.contact.zones[0];
    const auto  &body = scene.bodies[zone.body];
    const bool   pair = zone.type == Parameters::ContactZone::Type::body;
    const double R    = scene.verification.hertz.sphere_radius > 0 ?
                          scene.verification.hertz.sphere_radius :
                        zone.type == Parameters::ContactZone::Type::rigid_sphere ?
                          zone.radius :
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
    return 1 / (compliance(zone.body) + (zone.type == Parameters::ContactZone::Type::body ?
                                           compliance(zone.master_body) :
                                           0.0));
  }

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

    // The touch point, and the ray from it along x projected on the plane.
    const unsigned int centre = *std::min_element(zone_nodes.begin(),
                                                  zone_nodes.end(),
                                                  [&](const unsigned int i, const unsigned int j) {
                                                    return nodes[i].gap < nodes[j].gap;
                                                  });
    h.p0                      = pressure(centre);
    const Tensor<1, 3> &n     = nodes[centre].n;
    Tensor<1, 3>        dir   = Tensor<1, 3>({1., 0., 0.}) - n[0] * n;
    require(dir.norm() > 1e-6,
            "Verification/Hertz: the contact normal is along x; the ray needs another direction.");
    dir /= dir.norm();
    const Tensor<1, 3> across = cross_product_3d(n, dir);
    double             extent = 0;
    for (const unsigned int k : zone_nodes)
      extent = std::max(extent, (nodes[k].x - nodes[centre].x).norm());
    std::vector<std::pair<double, unsigned int>> ray; // (r, node), the touch point included
    for (const unsigned int k : zone_nodes)
      {
        const Tensor<1, 3> d = nodes[k].x - nodes[centre].x;
        if (std::abs(d * across) <= 1e-9 * extent && d * dir >= 0)
          ray.emplace_back(d * dir, k);
      }
    std::sort(ray.begin(), ray.end());
    require(ray.size() >= 2,
            "Verification/Hertz: fewer than two contact nodes on the ray from the touch point "
            "along x; the mesh must have a line of nodes there (a symmetry plane).");
    double p_max = 0;
    for (const auto &[r, k] : ray)
      p_max = std::max(p_max, pressure(k));
    require(p_max > 0, "Verification/Hertz: no node on the ray is in contact.");
    std::vector<std::pair<double, double>> in_contact; // (r, p)
    double                                 bound = -1;
    for (const auto &[r, k] : ray)
      if (pressure(k) > 1e-6 * p_max)
        in_contact.emplace_back(r, pressure(k));
    const double r_last = in_contact.back().first;
    for (const auto &[r, k] : ray)
      if (r > r_last)
        {
          bound = r;
          break;
        }
    if (bound < 0)
      bound = r_last;
    h.a = r_last;
    if (in_contact.size() >= 2)
      {
        // p² linear in r²: zero at r² = r2² + p2² (r2² − r1²) / (p1² − p2²).
        const auto [r1, p1] = in_contact[in_contact.size() - 2];
        const auto [r2, p2] = in_contact.back();
        const double s1 = r1 * r1, s2 = r2 * r2, q1 = p1 * p1, q2 = p2 * p2;
        const double a2 = q1 > q2 ? s2 + q2 * (s2 - s1) / (q1 - q2) : s2;
        h.a             = std::min(std::sqrt(a2), bound);
      }
    for (const auto &[r, p] : in_contact)
      if (r > 0 && r <= h.a)
        ++h.nodes_across_a;
    return h;
  }
} // namespace FetiContact
