#pragma once

#include <feticontact/contact/contact_geometry.h>

#include <optional>
#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * @brief The friction law of the zones with a friction coefficient μ > 0: how the slip bound
   * g of every contact node follows from the normal forces.
   *
   * Coulomb: g_k = μ_k (λ_N,k)⁺, plus at a vertex shared by several zones the bounds of the
   * nodes whose keeper is k (slip_bounds() of contact_nodes.h); the fixed point g = μ λ_N is
   * found by the method of successive approximations. Tresca: a given g for every node with
   * μ > 0, one QP. Frictionless nodes (μ = 0) have g = 0 under either law.
   */
  class FrictionLaw
  {
  public:
    /** Coulomb's law. */
    static FrictionLaw
    coulomb();

    /** Tresca's law with the slip bound @p g (a nodal force, N) for every node with μ > 0. */
    static FrictionLaw
    tresca(const double g);

    /** Whether g depends on the normal forces (Coulomb): then it is a fixed point. */
    bool
    depends_on_normal_force() const;

    /** Tresca's g, or nothing for Coulomb. */
    std::optional<double>
    tresca_slip_bound() const;

    /** The slip bounds g_k (N) for the normal forces @p normal_force (N) of the nodes. */
    std::vector<double>
    slip_bounds(const std::vector<ContactNode> &nodes,
                const std::vector<double>      &normal_force) const;

    /** The constraint set in words, for messages: the cones, or the Tresca bounds. */
    std::string
    constraint_description() const;

  private:
    explicit FrictionLaw(const std::optional<double> tresca_bound);

    /** Tresca's g, or empty for Coulomb. */
    std::optional<double> tresca_bound;
  };
} // namespace FetiContact
