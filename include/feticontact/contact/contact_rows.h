#pragma once

#include <feticontact/contact/contact_geometry.h>
#include <feticontact/feti/equality_constraints.h>

#include <memory>
#include <vector>

namespace FetiContact
{
  /**
   * Where the contact multipliers sit in λ = [λ_T; λ_N; λ_E] (DESIGN.md §2): first the
   * tangential pairs (λ_T1, λ_T2) of the contact nodes with friction, contiguous per node (the
   * disc blocks), then one normal multiplier λ_N per contact node (λ_N ≥ 0), then the equality
   * multipliers λ_E (gluing, TFETI Dirichlet rows).
   */
  struct DualLayout
  {
    unsigned int n_tangential = 0; ///< 2 × the number of contact nodes with F > 0
    unsigned int n_normal     = 0; ///< the number of contact nodes
    unsigned int n_equality   = 0;

    /** Per contact node: its row in λ_N (absolute index in λ). */
    std::vector<unsigned int> normal_row;
    /** Per contact node: the first of its two tangential rows, or invalid if F = 0. */
    std::vector<unsigned int> tangential_row;

    unsigned int
    first_normal() const
    {
      return n_tangential;
    }
    unsigned int
    first_equality() const
    {
      return n_tangential + n_normal;
    }
    unsigned int
    size() const
    {
      return n_tangential + n_normal + n_equality;
    }
  };

  /**
   * The rows of B_t = [T1; T2] and N with their right-hand sides (0 and the gaps d), for the
   * contact nodes: (u^p(x_k) − u^q(χ(x_k)))·v for v = t1_k, t2_k, n_k, or u^p(x_k)·v for a rigid
   * obstacle. A node on a subdomain interface uses the copy in its lowest-numbered subdomain
   * (the copies are glued). Fills @p layout except n_equality.
   */
  DualRows
  build_contact_rows(const std::vector<ContactNode>           &nodes,
                     const std::vector<std::unique_ptr<Body>> &bodies,
                     const std::vector<unsigned int>          &first_subdomain,
                     DualLayout                               &layout);
} // namespace FetiContact
