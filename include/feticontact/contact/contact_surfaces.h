#pragma once

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <feticontact/base/regions.h>
#include <feticontact/scene/body.h>
#include <feticontact/scene/boundary_selector.h>

#include <array>
#include <functional>
#include <map>
#include <vector>

namespace FetiContact
{
  /**
   * What the rows of B need of a body vertex besides its number: the parts of its body that hold
   * a copy of it (increasing) and its prescribed displacement components (Γ_u).
   */
  struct VertexCopies
  {
    std::vector<unsigned int> parts;
    Body::Prescribed          prescribed;
  };

  /** A triangle of a zone's surface: its body-mesh vertices and their positions. */
  struct ContactTriangle
  {
    unsigned int                    zone;
    unsigned int                    body;
    std::array<unsigned int, 3>     vertices;
    std::array<dealii::Point<3>, 3> points;
    /** The outward normal times the area. */
    dealii::Tensor<1, 3> outward;
    /** The part of the body's partition whose cell has the triangle as a face. */
    unsigned int part;
    /**
     * Per vertex: its home part, the lowest part of the body's partition that holds a copy of
     * it (the part whose rank holds the vertex's contact nodes, build_contact_rows()).
     */
    std::array<unsigned int, 3> home;
  };

  /**
   * The triangles of the zones' surfaces that a rank lists: of every zone's (slave) surface, and
   * of the master surface of every body-pair zone; all of them where every rank holds the whole
   * meshes, else those of the rank's cells (find_contact_nodes()). The contact output and the
   * checks after the solve read them instead of the bodies' meshes.
   */
  struct ContactSurfaces
  {
    std::vector<ContactTriangle> slave, master;

    /** A vertex of a body's surface, with its position and its home part. */
    struct Vertex
    {
      unsigned int     zone;
      unsigned int     body;
      unsigned int     vertex;
      dealii::Point<3> x;
      unsigned int     home;
    };

    /**
     * The slave vertices of the body-pair zones that are no contact node of their zone (beyond
     * the search distance, or clamped): the home vertices of this rank (all with the whole
     * search). surface_penetration() checks them against the master surface.
     */
    std::vector<Vertex> uncoupled;
  };

  /**
   * The depth, relative to the local mesh size h (the mean edge of the surface triangles around
   * the node), up to which a node that starts inside a rigid obstacle or the master body counts
   * as touching it: its initial gap is 0 (ZoneReport::n_touching counts them). Deeper the run is
   * refused (the bodies overlap before any load), unless a zone's search distance admits it.
   *
   * 1e-8 h is the resolution of the scene's geometry on the scale of the mesh, the tolerance of
   * the project's other geometric tests (a surface plane `z = …` holds the vertices within 1e-8
   * of the body's diagonal, matching nodes coincide within 1e-8 h). Rounding in the input lies
   * below it: a plane normal written to 10 digits (a direction error up to 5e-11) places the
   * plane within 5e-11 of the distance from its point, 1e-8 h on a surface up to 200 cells
   * across (written to 12 digits: 20,000). Counting such an overlap as contact moves the
   * solution by at most that depth: a strain of 1e-8, far below the discretization error.
   */
  constexpr double touching_fraction = 1e-8;
} // namespace FetiContact

/**
 * The pieces of the contact search (find_contact_nodes()) that its files share:
 * contact_surfaces.cc (the surfaces and their exchange between the ranks), obstacle_nodes.cc,
 * body_pair_search.cc and contact_nodes.cc. Not for use outside the search.
 */
namespace FetiContact::ContactSearch
{
  using dealii::BoundingBox;
  using dealii::Point;
  using dealii::Tensor;

  /** A vertex of a surface: its position and its copies. */
  struct SurfaceVertex
  {
    Point<3>     x;
    VertexCopies copies;
    /** Whether this rank finds the vertex's contact nodes (its home vertices, or all). */
    bool home = true;
  };

  /**
   * A boundary face of a body in a surface, as the rank that holds its cell sees it: the key
   * (the cell's active index in the body and the face's number in it) that orders the faces
   * of all ranks as one whole mesh would, and what the surface needs of it.
   */
  struct SurfaceFace
  {
    std::array<unsigned int, 2> key;
    std::array<unsigned int, 3> vertex; ///< body vertices
    std::array<Point<3>, 3>     point;
    Tensor<1, 3>                area_normal; ///< outward
    double                      edges = 0;   ///< the sum of the lengths of the three edges
    unsigned int                part  = 0;
    /** Per vertex: the parts that hold it, and its prescribed components (NaN: none). */
    std::array<std::vector<unsigned int>, 3> holders;
    std::array<std::array<double, 3>, 3>     prescribed;
    /** Whether this rank holds the face's cell (not sent). */
    bool own = false;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int /*version*/)
    {
      archive &key &vertex &point &area_normal &edges &part &holders &prescribed;
    }

    BoundingBox<3>
    box() const
    {
      return BoundingBox<3>(std::vector<Point<3>>(point.begin(), point.end()));
    }
  };

  /**
   * The vertices of the boundary faces of a body in a surface (all faces, or the faces a rank
   * needs), with their positions and copies, the area-weighted sum of the outward normals of
   * those faces, the area lumped at each vertex, and the mean edge length of all faces of the
   * surface.
   */
  struct Surface
  {
    std::map<unsigned int, SurfaceVertex> vertex;
    std::map<unsigned int, Tensor<1, 3>>  normal_sum;
    std::map<unsigned int, double>        area; ///< a third of each adjacent triangle
    /** The sum of the edge lengths of the triangles at each vertex, and their number. */
    std::map<unsigned int, std::pair<double, unsigned int>> edges_at;
    double                                                  mean_edge = 0;
    std::vector<std::array<unsigned int, 3>>                triangles;
    std::vector<Tensor<1, 3>> outward; ///< per triangle, area-weighted
    std::vector<unsigned int> part;    ///< per triangle, the part of its cell
    /** Per triangle: whether this rank holds its cell (each triangle is own on one rank). */
    std::vector<bool> own;

    /**
     * The local mesh size at @p v: the mean length of the edges of the triangles around it
     * (complete at the vertices whose nodes this rank finds).
     */
    double
    local_edge(const unsigned int v) const
    {
      const auto &[length, count] = edges_at.at(v);
      return length / (3 * count);
    }

    /**
     * The depth up to which the node at vertex @p v that starts inside an obstacle or the
     * master body counts as touching it (its gap is 0): touching_fraction times the local
     * mesh size. Deeper, the bodies overlap before any load.
     */
    double
    touching_depth(const unsigned int v) const
    {
      return touching_fraction * local_edge(v);
    }

    /**
     * Appends the triangles this rank holds to @p list as triangles of zone @p zone on body
     * @p body.
     */
    void
    append_to(std::vector<ContactTriangle> &list,
              const unsigned int            zone,
              const unsigned int            body) const
    {
      for (unsigned int t = 0; t < triangles.size(); ++t)
        if (own[t])
          {
            ContactTriangle triangle{zone, body, triangles[t], {}, outward[t], part[t], {}};
            for (unsigned int v = 0; v < 3; ++v)
              {
                const SurfaceVertex &corner = vertex.at(triangles[t][v]);
                triangle.points[v]          = corner.x;
                triangle.home[v]            = corner.copies.parts.front();
              }
            list.push_back(triangle);
          }
    }
  };

  /** How a surface is collected: which faces a rank takes, and whose nodes it finds. */
  enum class Share
  {
    /** Every face of the surface, and the nodes of every vertex. */
    whole,
    /**
     * The faces around the rank's home vertices (those whose lowest part it holds) and around
     * their neighbours: the nodes of the home vertices, with the normals of their neighbours.
     */
    home_rings
  };

  /**
   * The faces of @p surface of @p body whose cells this rank holds; @p parts_of_vertex is
   * Body::parts_of_mesh_vertices().
   */
  std::vector<SurfaceFace>
  own_faces(const Body                                   &body,
            const BoundarySelector                       &surface,
            const std::vector<std::vector<unsigned int>> &parts_of_vertex);

  /**
   * @p faces with those that @p outgoing sends to this rank and those the other ranks send
   * it (not twice), in the order of their keys. Collective on the body's mesh_comm().
   */
  std::vector<SurfaceFace>
  exchange_faces(const Body                                             &body,
                 std::vector<SurfaceFace>                                faces,
                 const std::map<unsigned int, std::vector<SurfaceFace>> &outgoing);

  /**
   * The faces of all ranks that meet the region @p regions gives this rank (widened by
   * @p margin), from the faces @p own that this rank holds: @p regions has the region of every
   * rank of the body's mesh_comm(), or nothing for a rank that needs none. Collective.
   */
  std::vector<SurfaceFace>
  faces_in_regions(const Body                         &body,
                   const std::vector<SurfaceFace>     &own,
                   const std::vector<Regions::Region> &regions,
                   const double                        margin);

  /** The bounding box of the points of @p faces, or nothing if there are none. */
  Regions::Region
  box_of(const std::vector<SurfaceFace> &faces);

  /**
   * The surface of @p faces (in the order of their keys); a vertex is a home vertex if
   * @p home says so. @p mean is the mean edge of the whole surface.
   */
  Surface
  surface_of(const std::vector<SurfaceFace>                               &faces,
             const double                                                  mean,
             const std::function<bool(const SurfaceFace &, unsigned int)> &home);

  /**
   * The surface @p surface of @p body; @p parts_of_vertex is Body::parts_of_mesh_vertices().
   * Whole: with the body's cells distributed, the faces of all ranks are gathered, so that
   * every rank has the same surface, to the bit, on any number of ranks. Home rings: the faces
   * around this rank's home vertices and their neighbours, in the order of the whole surface
   * (so that the sums at a home vertex are the same bits). Collective.
   */
  Surface
  collect_surface(const Body                                   &body,
                  const BoundarySelector                       &surface,
                  const std::vector<std::vector<unsigned int>> &parts_of_vertex,
                  const Share                                   share);

  /** The bounding box of the vertices of the triangles of @p s this rank holds. */
  Regions::Region
  box_of_own(const Surface &s);

  /** The bounding box of all vertices of @p s, or nothing. */
  Regions::Region
  box_of_all(const Surface &s);
} // namespace FetiContact::ContactSearch
