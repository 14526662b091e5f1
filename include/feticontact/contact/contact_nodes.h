#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <feticontact/contact/contact_surfaces.h>
#include <feticontact/scene/body.h>
#include <feticontact/scene/contact_parameters.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace FetiContact
{
  /** A master vertex of a contact node's row and its weight M_kj / D_kk. */
  struct MasterPoint
  {
    unsigned int body;
    unsigned int vertex;
    double       weight;
    /** Its position and copies. */
    dealii::Point<3> y;
    VertexCopies     copies;

    bool
    operator==(const MasterPoint &other) const
    {
      return body == other.body && vertex == other.vertex && weight == other.weight;
    }
  };

  /**
   * A contact node x_k of a slave surface Γ_c (doc/formulation.md, "The continuous problem"): the
   * vertex, what it is held against, the critical direction n_k, tangents t1_k, t2_k ({n, t1, t2}
   * orthonormal), the initial gap d_k and the coefficient of friction μ of its zone.
   *
   * Its rows are v·(u(x_k) − Σ_j w_j u(y_j)) ≤ c for v = t1_k, t2_k (c = 0) and n_k (c = d_k),
   * with the master vertices y_j and weights w_j of @p master: one vertex χ(x_k) of weight 1
   * for a body pair discretized node to node, the mortar weights M_kj / D_kk (doc/contact.md,
   * "Non-matching meshes") for a mortar pair, none for a rigid obstacle. The weights sum to 1.
   */
  struct ContactNode
  {
    unsigned int zone;
    unsigned int body;
    unsigned int vertex;
    /** The master vertices and their weights; empty for a rigid obstacle. */
    std::vector<MasterPoint> master;
    dealii::Point<3>         x;
    /** The copies of the slave vertex. */
    VertexCopies         copies;
    dealii::Tensor<1, 3> n, t1, t2;
    /**
     * The initial gap: (χ(x_k) − x_k)·n_k node to node and on an obstacle; the weighted gap
     * g̃_k / D_kk for a mortar node (negative: an initial overlap, which the solve removes).
     */
    double gap      = 0;
    double friction = 0;
    /**
     * The area of the slave surface lumped at the node (a third of each adjacent triangle):
     * λ_N / area is the mean contact pressure around the node.
     */
    double area = 0;
    /**
     * The area that turns the node's forces into pressures: D_kk of the mortar rows (the
     * dual-basis area; the covered part of the lumped area at the edge of a mortar zone), the
     * lumped area otherwise.
     */
    double pressure_area = 0;
    /** Whether the node's rows are mortar rows. */
    bool mortar = false;
    /**
     * For a node at a vertex shared with other zones whose tangential rows another node of the
     * vertex carries (combine_shared_vertices): that node's index. This node's μ λ_N adds to
     * that node's slip bound (slip_bounds()).
     */
    std::optional<unsigned int> keeper;

    /** Whether the node is held against another body (node to node or mortar). */
    bool
    on_body() const
    {
      return !master.empty();
    }
  };

  /**
   * Displacements of some vertices of the bodies (those of the contact surfaces), by body and
   * body vertex.
   */
  class VertexDisplacements
  {
  public:
    explicit VertexDisplacements(const unsigned int n_bodies = 0)
      : of_body(n_bodies)
    {}

    /** Sets the displacement of vertex @p vertex of body @p body. */
    void
    set(const unsigned int body, const unsigned int vertex, const dealii::Tensor<1, 3> &u)
    {
      of_body[body][vertex] = u;
    }

    /** The displacement of vertex @p vertex of body @p body; throws if it is not held. */
    const dealii::Tensor<1, 3> &
    operator()(const unsigned int body, const unsigned int vertex) const
    {
      return of_body[body].at(vertex);
    }

  private:
    std::vector<std::unordered_map<unsigned int, dealii::Tensor<1, 3>>> of_body;
  };

  /**
   * The displacement of node @p node relative to what it is held against,
   * u(x_k) − Σ_j w_j u(y_j), from the displacements @p u of its vertices.
   */
  dealii::Tensor<1, 3>
  relative_displacement(const ContactNode &node, const VertexDisplacements &u);

  /** Σ_j w_j y_j: the point of the master surface that node @p node is held against. */
  dealii::Point<3>
  master_point(const ContactNode &node);

  /** How a zone's rows were built: for the log and summary.json. */
  struct ZoneReport
  {
    /** "rigid plane", "rigid obstacle" (a curved one), "node to node" or "mortar". */
    std::string  discretization;
    unsigned int n_nodes = 0;
    /** Mortar: slave vertices that no master triangle covers (not contact nodes). */
    unsigned int n_uncovered = 0;
    /** Mortar: nodes covered in part (weighted by φ_k instead of ψ_k). */
    unsigned int n_partly_covered = 0;
    /** Nodes with a negative initial gap (mortar: an overlap within the search distance). */
    unsigned int n_overlapping = 0;
    /**
     * Nodes that start inside the obstacle or the master body by less than touching_fraction of
     * the local mesh size: their gap is 0 (they touch).
     */
    unsigned int n_touching = 0;
    /** Mortar: the search distance used and the segments integrated. */
    double       search_distance = 0;
    unsigned int n_segments      = 0;
  };

  /** The bytes that @p nodes and @p surfaces hold. */
  std::size_t
  memory_consumption(const std::vector<ContactNode> &nodes, const ContactSurfaces &surfaces);

  /**
   * The contact nodes of all zones: the vertices of each zone's surface that have no prescribed
   * displacement component, or only components orthogonal to the node's normal, such as a
   * symmetry plane's roller condition (then t2 is the last prescribed axis, whose tangential row
   * acts on no free DoF), in zone order and by vertex number. A vertex on the surfaces of several
   * zones is a node of each (see combine_shared_vertices in contact_nodes.cc: the first keeps
   * the tangents orthogonal to all normals of the vertex, the others none). Rigid plane: χ(x_k) is
   * the orthogonal projection of x_k on the plane and n_k the plane's normal pointing into the
   * obstacle. Body pair: n_k is from x_k towards χ(x_k) when the gap is positive and the outer unit
   * normal of Γ_c (the area-weighted mean of the adjacent face normals) when it is zero. For a body
   * pair discretized node to node every slave node must have a master vertex opposite it along
   * its normal; otherwise the surfaces do not match and InputError names the node. A mortar pair
   * (doc/contact.md, "Non-matching meshes") has the slave vertices that the master surface
   * covers within the search distance, with n_k the mean outer normal at the vertex. If
   * @p surfaces is given, the triangles of the zones' surfaces are appended to it (those whose
   * cells this rank holds); if @p reports is given, one report per zone (of all ranks).
   *
   * With @p home_nodes and the bodies' cells distributed over the ranks (Body::distributed()),
   * the search is shared (doc/contact.md, "The contact search on several ranks"): a rank finds
   * the nodes of its home vertices only, those whose home part (the lowest part that holds a
   * copy) it holds, from the slave faces around them and the master faces near them, which the
   * other ranks send it. They are the nodes that one rank finds at those vertices, to the bit,
   * in the same order. Otherwise every rank finds every node. Collective on the bodies' ranks.
   */
  std::vector<ContactNode>
  find_contact_nodes(const std::vector<std::unique_ptr<Body>> &bodies,
                     const Parameters::Contact                &contact,
                     ContactSurfaces                          *surfaces   = nullptr,
                     std::vector<ZoneReport>                  *reports    = nullptr,
                     const bool                                home_nodes = false);

  /** Unit vectors t1, t2 completing the unit vector n to a right-handed orthonormal basis. */
  std::pair<dealii::Tensor<1, 3>, dealii::Tensor<1, 3>>
  tangent_basis(const dealii::Tensor<1, 3> &n);
  /**
   * The Coulomb slip bounds of the nodes in the units of the forces, from their normal forces
   * @p normal_force: g_k = F_k (λ_N,k)⁺ plus, at a vertex shared by several zones, F_j (λ_N,j)⁺
   * of every node j whose keeper is k (the friction of every zone acts along the directions
   * that the keeper's tangential rows span).
   */
  std::vector<double>
  slip_bounds(const std::vector<ContactNode> &nodes, const std::vector<double> &normal_force);
} // namespace FetiContact

/**
 * The pieces of find_contact_nodes() that the searches of the kinds of zones share
 * (obstacle_nodes.cc, body_pair_search.cc).
 */
namespace FetiContact::ContactSearch
{
  /** @p p as "(x, y, z)" for messages (−0 printed as 0). */
  std::string
  point_text(const Tensor<1, 3> &p);

  /**
   * The text that tells how deep a node may start inside: the touching depth at vertex @p v of
   * @p slave and the local mesh size it is relative to.
   */
  std::string
  touching_text(const Surface &slave, const unsigned int v);

  /** Replaces each of @p counts by its sum over the ranks of @p comm. Collective. */
  void
  add_over_ranks(const std::vector<unsigned int *> &counts, const MPI_Comm comm);

  /** The slave side of a zone: its body, its surface and the start of every node. */
  struct ZoneSide
  {
    /** The zone's number (0-based) and parameters, its (slave) body and surface. */
    unsigned int                   z;
    const Parameters::ContactZone &zone;
    const Body                    &body;
    const Surface                 &slave;
    /** "Contact zone N: ", the start of the zone's messages. */
    std::string where;
    /** Where the zone's triangles go (or nullptr). */
    ContactSurfaces *surfaces;
    /** parts_of_vertices() of a body, computed once per body. */
    const std::function<const std::vector<std::vector<unsigned int>> &(const Body &)>
      &parts_of_vertex;
    /** The zone's (slave) surface. */
    const BoundarySelector &selector;
    /** Share::whole, or Share::home_rings: this rank's share of the search. */
    Share share;
    /** The ranks of the search (MPI_COMM_SELF for the whole). */
    MPI_Comm comm;

    /** Whether every rank searches its share only. */
    bool
    shared() const
    {
      return share == Share::home_rings;
    }

    /**
     * The node at @p vertex with the fields common to every discretization, or nothing if the
     * vertex is clamped.
     */
    std::optional<ContactNode>
    start_node(const unsigned int vertex) const;

    /**
     * Completes @p node with its tangents and appends it to @p nodes, unless a prescribed
     * component acts along its normal.
     */
    void
    finish_node(ContactNode &node, std::vector<ContactNode> &nodes) const;
  };
} // namespace FetiContact::ContactSearch
