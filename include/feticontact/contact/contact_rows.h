#pragma once

#include <feticontact/contact/contact_geometry.h>
#include <feticontact/feti/equality_constraints.h>

#include <functional>
#include <memory>
#include <vector>

namespace FetiContact
{
  /**
   * Where the contact multipliers sit in λ = [λ_T; λ_N; λ_E] (doc/formulation.md, "The constraint
   * rows"): first the tangential pairs (λ_T1, λ_T2) of the contact nodes with friction, contiguous
   * per node (the disc blocks), then one normal multiplier λ_N per contact node (λ_N ≥ 0), then the
   * equality multipliers λ_E (gluing, TFETI Dirichlet rows).
   */
  struct DualLayout
  {
    unsigned int n_tangential = 0; ///< tangential rows: per node with μ > 0, 2 (disc) or s
    /** Tangential rows per node with friction: 2 for the disc, s for the polygonal baseline. */
    unsigned int tangential_per_node = 2;
    /** Whether the tangential rows are the polygonal baseline's s directions. */
    bool         polygonal  = false;
    unsigned int n_normal   = 0; ///< the number of contact nodes
    unsigned int n_equality = 0;

    /** Per contact node: its row in λ_N (absolute index in λ). */
    std::vector<unsigned int> normal_row;
    /** Per contact node: the first of its tangential rows, or invalid if μ = 0. */
    std::vector<unsigned int> tangential_row;
    /**
     * Per contact node: the factor σ_k by which its rows are scaled (1 unless the rows average
     * the copies of an interface node). Its multipliers are the contact force divided by σ_k.
     */
    std::vector<double> node_scale;

    /** σ_k of contact node @p k (1 if node_scale was not filled). */
    double
    scale_of_node(const unsigned int k) const
    {
      return node_scale.empty() ? 1.0 : node_scale[k];
    }

    /** The number of contact node @p k among the nodes of all ranks (its normal row's place). */
    unsigned int
    node_number(const unsigned int k) const
    {
      return normal_row[k] - n_tangential;
    }

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
   * (the copies are glued), or with @p average the mean of its p copies, v·(u_1 + … + u_p)/p,
   * scaled by σ_k = √p (√((1 + 1)/(1/p + 1/q)) with a master node of q copies) so that the row
   * keeps its length and is orthogonal to the gluing rows; the gap is scaled by σ_k as well.
   * Fills @p layout except n_equality.
   *
   * With @p polygon_directions = s > 0 (the polygonal baseline of the paper's Table 3) a node
   * with friction gets s tangential rows along d_j = cos(πj/s) t1 + sin(πj/s) t2, j = 0 … s−1,
   * instead of the two rows along t1 and t2.
   *
   * The rows of all nodes at one slave vertex (of several zones at an edge or corner,
   * combine_shared_vertices in contact_nodes.cc) are held together (DualRows::held_together)
   * by the vertex's home subdomain, the lowest of its copies (DualRows::held_by): the rank of
   * that subdomain holds them, sets the node's constraints and adds up the slip bound of the
   * vertex's keeper (slip_bounds()).
   */
  DualRows
  build_contact_rows(const std::vector<ContactNode>  &nodes,
                     const std::vector<unsigned int> &first_subdomain,
                     DualLayout                      &layout,
                     const unsigned int               polygon_directions = 0,
                     const bool                       average            = false);

  /**
   * The contact rows of the nodes of all ranks of @p comm, each rank giving the nodes of its
   * home vertices (find_contact_nodes() with home_nodes), with the numbers that
   * build_contact_rows() gives them with all nodes: a node's place among the nodes of all ranks
   * (in the order of zones and vertices) is summed over the ranks, without any rank holding all
   * nodes (number_by_keys()). Every rank gets the rows that touch its subdomains (@p owner: the
   * rank of every subdomain) with the rows held together with them, or with @p to_all all rows.
   * @p layout gets the counts of all rows, and the per-node arrays of this rank's nodes.
   * Collective.
   */
  DualRows
  build_shared_contact_rows(const MPI_Comm                   comm,
                            const std::vector<ContactNode>  &nodes,
                            const std::vector<unsigned int> &first_subdomain,
                            const std::vector<unsigned int> &owner,
                            DualLayout                      &layout,
                            const unsigned int               polygon_directions,
                            const bool                       average,
                            const bool                       to_all);

  /** Contact nodes with their layout (DualLayout's per-node arrays in the order of the nodes). */
  struct HeldContactNodes
  {
    std::vector<ContactNode> nodes;
    DualLayout               layout;
  };

  /**
   * The nodes k of @p nodes (of all ranks) for which @p holds_node(k) is true, in the same
   * order, with the keepers (ContactNode::keeper) renumbered to them and, if @p layout lays out
   * @p nodes (its per-node arrays are theirs), the per-node arrays of the layout; the counts of
   * @p layout (rows of all ranks) are kept. A rank holds the nodes of its home subdomains, whose
   * rows it holds (build_contact_rows()): the nodes at one vertex together, so a held node's
   * keeper is held too.
   */
  HeldContactNodes
  hold_contact_nodes(const std::vector<ContactNode>                &nodes,
                     const DualLayout                              &layout,
                     const std::function<bool(const unsigned int)> &holds_node);
} // namespace FetiContact
