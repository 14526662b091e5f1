#pragma once

#include <feticontact/base/json_writer.h>
#include <feticontact/contact/contact_geometry.h>
#include <feticontact/contact/contact_results.h>
#include <feticontact/postprocessing/output_parameters.h>
#include <feticontact/scene/scene_parameters.h>

#include <ostream>
#include <vector>

namespace FetiContact
{
  /**
   * The contact of a body with a spherical bottom on a rigid plane against Hertz's solution
   * (doc/validation.md): E* = E/(1 − ν²), a = (3PR/(4E*))^(1/3), p0 = 3P/(2πa²),
   * p(r) = p0 √(1 − r²/a²).
   *
   * Measured from the nodal pressures p = λ_N / D_kk of contact zone 1 (the lumped pressure, the
   * mean of p over the node's patch) by a fit over the whole contact zone (doc/validation.md):
   *  - the touch point: the node of the zone with the smallest initial gap (on the sphere's
   *    axis where the mesh has a vertex there); r: a node's distance from it in the tangent
   *    plane there;
   *  - p0 and a: the weighted least-squares fit of p² = p0² − (p0²/a²) r², linear in r², over
   *    all pressed nodes of the zone (p > 1e-6 max p), each weighted by its lumped area (the fit
   *    approximates the L² fit of p² over the contact area), the nodes at the edge of the zone
   *    included: they hold where p² reaches zero.
   */
  struct HertzResult
  {
    /** Hertz: P, R, E*, a and p0. */
    double P = 0, R = 0, E_star = 0, a_hertz = 0, p0_hertz = 0;
    /** Measured: a, p0, and the normal contact force times the symmetry factor. */
    double a = 0, p0 = 0, total_normal_force = 0;
    /**
     * Contact nodes within the fitted radius on the ray from the touch point along x projected
     * on the tangent plane (for a quarter or half model: its symmetry line), the touch point
     * excluded; 0 where the mesh has no line of nodes there.
     */
    unsigned int nodes_across_a = 0;
    /** The pressure of the touch node alone, and the number of nodes of the fit. */
    double       p0_touch_node = 0;
    unsigned int n_fit_nodes   = 0;
    /** |a − a_H| / a_H and |p0 − p0_H| / p0_H. */
    double
    a_error() const;
    double
    p0_error() const;

    JsonObject
    json() const;
    /** A few lines for log.txt. */
    void
    print(std::ostream &out) const;
  };

  /**
   * The radius R of Hertz's sphere for zone 1 of @p scene: `Verification/Hertz/Sphere radius`,
   * else the radius of a rigid sphere, else the `Spherical bottom radius` of the zone's body or,
   * for a body pair, of its master body.
   */
  double
  hertz_radius(const Parameters::Scene &scene);

  /**
   * Hertz's E* for zone 1 of @p scene: 1/E* = (1 − ν₁²)/E₁ for a rigid obstacle, plus
   * (1 − ν₂²)/E₂ of the master body for a body pair.
   */
  double
  hertz_modulus(const Parameters::Scene &scene);

  /**
   * Evaluates zone 1 of @p scene (a rigid plane or sphere, or a body pair, with hertz_radius()
   * and hertz_modulus()) from the pressures λ_N / D_kk of its nodes. Throws InputError when the
   * scene does not fit (no radius, nothing in contact, pressures that do not fall outwards).
   */
  HertzResult
  compare_with_hertz(const Parameters::Scene              &scene,
                     const std::vector<ContactNode>       &nodes,
                     const std::vector<ContactNodeResult> &results);
} // namespace FetiContact
