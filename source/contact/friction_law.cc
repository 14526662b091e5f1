#include <feticontact/contact/friction_law.h>

#include <cmath>

namespace FetiContact
{
  FrictionLaw::FrictionLaw(const std::optional<double> tresca_bound)
    : tresca_bound(tresca_bound)
  {}

  FrictionLaw
  FrictionLaw::coulomb()
  {
    return FrictionLaw(std::nullopt);
  }

  FrictionLaw
  FrictionLaw::tresca(const double g)
  {
    return FrictionLaw(g);
  }

  bool
  FrictionLaw::depends_on_normal_force() const
  {
    return !tresca_bound;
  }

  std::optional<double>
  FrictionLaw::tresca_slip_bound() const
  {
    return tresca_bound;
  }

  std::vector<double>
  FrictionLaw::slip_bounds(const std::vector<ContactNode> &nodes,
                           const std::vector<double>      &normal_force) const
  {
    if (!tresca_bound)
      return FetiContact::slip_bounds(nodes, normal_force);
    std::vector<double> g(nodes.size(), 0.0);
    for (unsigned int k = 0; k < nodes.size(); ++k)
      if (nodes[k].friction > 0)
        g[k] = *tresca_bound;
    return g;
  }

  std::string
  FrictionLaw::constraint_description() const
  {
    return tresca_bound ? "the bounds λ_N ≥ 0, ‖λ_T‖ ≤ g (Tresca)" :
                          "the friction cones ‖λ_T‖ ≤ μ λ_N";
  }
} // namespace FetiContact
