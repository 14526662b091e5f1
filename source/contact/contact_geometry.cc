#include <deal.II/base/bounding_box.h>
#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_tools.h>

#include <feticontact/base/exact_sum.h>
#include <feticontact/base/input_parsing.h>
#include <feticontact/base/mpi_tools.h>
#include <feticontact/base/regions.h>
#include <feticontact/contact/contact_geometry.h>
#include <feticontact/contact/mortar.h>
#include <feticontact/contact/rigid_obstacle.h>

#include <boost/serialization/array.hpp>
#include <boost/serialization/vector.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <tuple>

namespace FetiContact
{
  using namespace dealii;

  std::pair<Tensor<1, 3>, Tensor<1, 3>>
  tangent_basis(const Tensor<1, 3> &n)
  {
    // Start from the coordinate axis least aligned with n.
    unsigned int axis = 0;
    for (unsigned int d = 1; d < 3; ++d)
      if (std::abs(n[d]) < std::abs(n[axis]))
        axis = d;
    Tensor<1, 3> a;
    a[axis]         = 1;
    Tensor<1, 3> t1 = a - (a * n) * n;
    t1 /= t1.norm();
    return {t1, cross_product_3d(n, t1)};
  }

  std::pair<double, Tensor<1, 3>>
  obstacle_distance(const Parameters::ContactZone &zone, const Point<3> &x)
  {
    return {zone.obstacle->signed_distance(x), -zone.obstacle->outward_normal(x)};
  }

  namespace
  {
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
              const std::vector<std::vector<unsigned int>> &parts_of_vertex)
    {
      std::vector<SurfaceFace> faces;
      for (const auto &cell : body.mesh.active_cell_iterators())
        for (const unsigned int f : cell->face_indices())
          {
            const auto face = cell->face(f);
            if (!face->at_boundary() || !surface.contains(*face))
              continue;
            SurfaceFace record;
            record.own = true;
            record.key = {{body.body_cell(cell->active_cell_index()), f}};
            for (unsigned int v = 0; v < 3; ++v)
              {
                const unsigned int mesh_vertex = face->vertex_index(v);
                record.vertex[v]               = body.body_vertex(mesh_vertex);
                record.point[v]                = face->vertex(v);
                record.holders[v]              = parts_of_vertex[mesh_vertex];
                record.prescribed[v].fill(std::numeric_limits<double>::quiet_NaN());
                const auto prescribed = body.prescribed.find(record.vertex[v]);
                if (prescribed != body.prescribed.end())
                  for (unsigned int c = 0; c < 3; ++c)
                    if (prescribed->second[c])
                      record.prescribed[v][c] = *prescribed->second[c];
              }
            const auto &[a, b, c] = record.point;
            record.area_normal    = 0.5 * cross_product_3d(b - a, c - a);
            if (record.area_normal * (face->center() - cell->center()) < 0)
              record.area_normal = -record.area_normal;
            record.edges = a.distance(b) + b.distance(c) + c.distance(a);
            record.part  = body.partition.part_of_cell[cell->active_cell_index()];
            faces.push_back(std::move(record));
          }
      return faces;
    }

    /** The rank (of the body's mesh_comm()) that finds the nodes of vertex @p v of @p face. */
    unsigned int
    home_rank(const Body &body, const SurfaceFace &face, const unsigned int v)
    {
      return body.rank_of_part(face.holders[v].front());
    }

    /**
     * @p faces with those that @p outgoing sends to this rank and those the other ranks send
     * it (not twice), in the order of their keys. Collective on the body's mesh_comm().
     */
    std::vector<SurfaceFace>
    exchange_faces(const Body                                             &body,
                   std::vector<SurfaceFace>                                faces,
                   const std::map<unsigned int, std::vector<SurfaceFace>> &outgoing)
    {
      for (const auto &[from, list] : Utilities::MPI::some_to_some(body.mesh_comm(), outgoing))
        faces.insert(faces.end(), list.begin(), list.end());
      // A face this rank holds first (own), then by key.
      std::sort(faces.begin(), faces.end(), [](const SurfaceFace &x, const SurfaceFace &y) {
        return x.key < y.key || (x.key == y.key && x.own && !y.own);
      });
      faces.erase(std::unique(faces.begin(),
                              faces.end(),
                              [](const SurfaceFace &x, const SurfaceFace &y) {
                                return x.key == y.key;
                              }),
                  faces.end());
      return faces;
    }

    /**
     * The faces of the stars of this rank's home vertices and of their neighbours (the normal
     * at a node's neighbours enters its mortar integrals), from the faces @p own this rank holds:
     * every face goes to the home ranks of its vertices, and every rank sends the star of each
     * of its home vertices to the home ranks of the vertex's neighbours. Collective.
     */
    std::vector<SurfaceFace>
    faces_of_home_rings(const Body &body, const std::vector<SurfaceFace> &own)
    {
      const unsigned int rank = Utilities::MPI::this_mpi_process(body.mesh_comm());
      std::map<unsigned int, std::vector<SurfaceFace>> outgoing;
      for (const SurfaceFace &face : own)
        {
          std::set<unsigned int> ranks;
          for (unsigned int v = 0; v < 3; ++v)
            ranks.insert(home_rank(body, face, v));
          for (const unsigned int r : ranks)
            if (r != rank)
              outgoing[r].push_back(face);
        }
      std::vector<SurfaceFace> stars = exchange_faces(body, own, outgoing);
      // The star of each home vertex v (complete here now) to the home ranks of its neighbours.
      std::map<unsigned int, std::vector<unsigned int>> star; // home vertex → faces
      std::map<unsigned int, std::set<unsigned int>>    ranks_of_neighbours;
      for (unsigned int f = 0; f < stars.size(); ++f)
        for (unsigned int v = 0; v < 3; ++v)
          if (home_rank(body, stars[f], v) == rank)
            {
              star[stars[f].vertex[v]].push_back(f);
              for (unsigned int w = 0; w < 3; ++w)
                ranks_of_neighbours[stars[f].vertex[v]].insert(home_rank(body, stars[f], w));
            }
      std::map<unsigned int, std::set<unsigned int>> faces_to; // rank → faces
      for (const auto &[v, faces] : star)
        for (const unsigned int r : ranks_of_neighbours[v])
          if (r != rank)
            faces_to[r].insert(faces.begin(), faces.end());
      outgoing.clear();
      for (const auto &[r, faces] : faces_to)
        for (const unsigned int f : faces)
          outgoing[r].push_back(stars[f]);
      return exchange_faces(body, std::move(stars), outgoing);
    }

    /**
     * The faces of all ranks that meet the region @p regions gives this rank (widened by
     * @p margin), from the faces @p own that this rank holds: @p regions has the region of every
     * rank of the body's mesh_comm(), or nothing for a rank that needs none. Collective.
     */
    std::vector<SurfaceFace>
    faces_in_regions(const Body                         &body,
                     const std::vector<SurfaceFace>     &own,
                     const std::vector<Regions::Region> &regions,
                     const double                        margin)
    {
      const unsigned int rank = Utilities::MPI::this_mpi_process(body.mesh_comm());
      std::map<unsigned int, std::vector<SurfaceFace>> outgoing;
      std::vector<SurfaceFace>                         kept;
      for (unsigned int r = 0; r < regions.size(); ++r)
        if (regions[r])
          {
            BoundingBox<3> region = *regions[r];
            region.extend(margin);
            for (const SurfaceFace &face : own)
              if (Regions::meet(region, face.box()))
                (r == rank ? kept : outgoing[r]).push_back(face);
          }
      return exchange_faces(body, std::move(kept), outgoing);
    }

    /** The bounding box of the points of @p faces, or nothing if there are none. */
    Regions::Region
    box_of(const std::vector<SurfaceFace> &faces)
    {
      Regions::Region box;
      for (const SurfaceFace &face : faces)
        Regions::merge(box, face.box());
      return box;
    }

    /**
     * The sum of the lengths of the edges of the faces of all ranks, each face once (by the
     * rank that holds its cell), exactly, and their number. Collective on @p comm.
     */
    double
    mean_edge(const std::vector<SurfaceFace> &faces, const MPI_Comm comm)
    {
      std::vector<ExactSum> sums(2);
      for (const SurfaceFace &face : faces)
        if (face.own)
          {
            sums[0].add(face.edges);
            sums[1].add(1);
          }
      ExactSum::sum_over_ranks(sums, comm);
      return sums[1].value() > 0 ? sums[0].value() / (3 * sums[1].value()) : 0;
    }

    /**
     * The surface of @p faces (in the order of their keys); a vertex is a home vertex if
     * @p home says so. @p mean is the mean edge of the whole surface.
     */
    Surface
    surface_of(const std::vector<SurfaceFace>                               &faces,
               const double                                                  mean,
               const std::function<bool(const SurfaceFace &, unsigned int)> &home)
    {
      Surface s;
      s.mean_edge = mean;
      for (const auto &face : faces)
        {
          for (unsigned int v = 0; v < 3; ++v)
            {
              const auto [entry, first_seen] = s.vertex.emplace(face.vertex[v], SurfaceVertex());
              if (first_seen)
                {
                  entry->second.x            = face.point[v];
                  entry->second.copies.parts = face.holders[v];
                  entry->second.home         = home(face, v);
                  for (unsigned int c = 0; c < 3; ++c)
                    if (!std::isnan(face.prescribed[v][c]))
                      entry->second.copies.prescribed[c] = face.prescribed[v][c];
                }
              s.normal_sum[face.vertex[v]] += face.area_normal;
              s.area[face.vertex[v]] += face.area_normal.norm() / 3;
              auto &[length, count] = s.edges_at[face.vertex[v]];
              length += face.edges;
              ++count;
            }
          s.triangles.push_back(face.vertex);
          s.outward.push_back(face.area_normal);
          s.part.push_back(face.part);
          s.own.push_back(face.own);
        }
      return s;
    }

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
                    const Share                                   share)
    {
      std::vector<SurfaceFace> faces = own_faces(body, surface, parts_of_vertex);
      const double             mean  = mean_edge(faces, body.mesh_comm());
      const unsigned int       rank  = Utilities::MPI::this_mpi_process(body.mesh_comm());
      if (share == Share::whole && body.distributed())
        {
          std::vector<SurfaceFace> all;
          for (auto &list : Utilities::MPI::all_gather(body.mesh_comm(), faces))
            all.insert(all.end(), list.begin(), list.end());
          std::sort(all.begin(), all.end(), [](const SurfaceFace &x, const SurfaceFace &y) {
            return x.key < y.key;
          });
          for (SurfaceFace &face : all)
            face.own = body.rank_of_part(face.part) == rank;
          faces = std::move(all);
        }
      else if (share == Share::home_rings && body.distributed())
        faces = faces_of_home_rings(body, faces);
      return surface_of(faces, mean, [&](const SurfaceFace &face, const unsigned int v) {
        return share != Share::home_rings || home_rank(body, face, v) == rank;
      });
    }

    std::string
    point_text(const Tensor<1, 3> &p)
    {
      // (+ 0.0 prints −0 as 0.)
      return '(' + InputParsing::number_text(p[0] + 0.0) + ", " +
             InputParsing::number_text(p[1] + 0.0) + ", " + InputParsing::number_text(p[2] + 0.0) +
             ')';
    }

    /**
     * A rigid plane's normal must point out of the obstacle, towards the body: against the
     * (area-weighted) outer normal of the zone's surface. Otherwise InputError names the zone
     * and the node whose outer normal points most along the plane's normal.
     */
    void
    check_plane_faces_body(const Surface                 &slave,
                           const Body                    &body,
                           const Parameters::ContactZone &zone,
                           const std::string             &where,
                           const MPI_Comm                 comm)
    {
      // The sums over the home vertices of all ranks, exact, and the vertex whose outer normal
      // points most along the plane's normal (the lowest vertex of the largest cosine).
      std::vector<ExactSum> sums(4);                          // Σ n (3), Σ |n|
      std::array<double, 8> worst{{-2, 0, 0, 0, 0, 0, 0, 0}}; // cosine, −vertex, normal, x
      for (const auto &[vertex, normal_sum] : slave.normal_sum)
        if (slave.vertex.at(vertex).home)
          {
            for (unsigned int d = 0; d < 3; ++d)
              sums[d].add(normal_sum[d]);
            sums[3].add(normal_sum.norm());
            const double c = normal_sum * zone.plane_normal / normal_sum.norm();
            if (c > worst[0])
              {
                worst = {{c, -static_cast<double>(vertex), 0, 0, 0, 0, 0, 0}};
                for (unsigned int d = 0; d < 3; ++d)
                  {
                    worst[2 + d] = normal_sum[d] / normal_sum.norm();
                    worst[5 + d] = slave.vertex.at(vertex).x[d];
                  }
              }
          }
      ExactSum::sum_over_ranks(sums, comm);
      for (const auto &other : Utilities::MPI::all_gather(comm, worst))
        if (other[0] > worst[0] || (other[0] == worst[0] && other[1] > worst[1]))
          worst = other;
      const Tensor<1, 3> total({sums[0].value(), sums[1].value(), sums[2].value()});
      const double       magnitude = sums[3].value(); // |total| below it: a curved surface
      const Tensor<1, 3> worst_normal({worst[2], worst[3], worst[4]});
      const Point<3>     worst_x(worst[5], worst[6], worst[7]);
      // Nearly perpendicular (within about 6°): the plane cannot face this surface. Only for a
      // surface whose normals point one way (|Σ n| ≥ 0.7 Σ|n|, arcs below about 160°): the mean
      // normal of a half cylinder or a closed surface says nothing about where it faces.
      const double cosine = total.norm() > 0 ? total * zone.plane_normal / total.norm() : 0;
      require(total.norm() < 0.7 * magnitude || std::abs(cosine) > 0.1,
              where + "the plane normal " + point_text(zone.plane_normal) +
                " is (nearly) perpendicular to the surface <" + zone.surface.name() +
                "> of body '" + body.parameters.name + "', whose mean outer normal is " +
                point_text(total / std::max(total.norm(), 1e-300)) + " (cosine " +
                InputParsing::number_text(cosine) +
                "): a rigid plane must face the surface it is paired with (a plane normal "
                "against that outer normal, or the surface that faces the plane).");
      require(total * zone.plane_normal < 0,
              where + "the plane normal " + point_text(zone.plane_normal) + " points into body '" +
                body.parameters.name + "': the outer normal of its surface <" +
                zone.surface.name() + "> is " + point_text(worst_normal) + " at the node at " +
                point_text(worst_x) +
                ". The plane normal must point out of the obstacle, towards the body (here " +
                point_text(-zone.plane_normal) + "?).");
    }

    /**
     * The vertices that lie on the surfaces of several zones (an edge or corner where two
     * obstacles meet, a body pair beside a plane). Every zone keeps its normal row, so the
     * vertex stays out of every obstacle; of rigid planes with the same normal only the one
     * with the smallest gap stays (it alone can bind: their gaps differ by a constant). The
     * tangential rows would repeat the normal rows of the other zones (the tangent plane of one
     * plane contains the normal of the other), and the multipliers would not be unique: one node
     * of the vertex, the keeper (the first with friction), keeps the tangential directions
     * orthogonal to every normal of the vertex (the edge's direction at an edge, none at a corner)
     * and the others keep none (t1 = t2 = 0: rows without entries, whose multipliers stay 0). The
     * friction of a node whose rows would act on the same motion as the keeper's (both on rigid
     * obstacles, or both against one master vertex) acts through the keeper's rows, whose slip
     * bound is the sum of those zones' μ λ_N (slip_bounds()); where a body pair meets a rigid
     * plane, only the keeper's zone has friction along the edge.
     */
    void
    combine_shared_vertices(std::vector<ContactNode> &nodes)
    {
      std::map<std::pair<unsigned int, unsigned int>, std::vector<unsigned int>> of_vertex;
      for (unsigned int k = 0; k < nodes.size(); ++k)
        of_vertex[{nodes[k].body, nodes[k].vertex}].push_back(k);
      std::vector<bool> dropped(nodes.size(), false);
      for (const auto &[vertex, ks] : of_vertex)
        {
          if (ks.size() < 2)
            continue;
          for (unsigned int a = 0; a < ks.size(); ++a)
            for (unsigned int b = a + 1; b < ks.size(); ++b)
              if (!dropped[ks[a]] && !dropped[ks[b]] && !nodes[ks[a]].on_body() &&
                  !nodes[ks[b]].on_body() && nodes[ks[a]].n * nodes[ks[b]].n > 1 - 1e-8)
                dropped[nodes[ks[a]].gap <= nodes[ks[b]].gap ? ks[b] : ks[a]] = true;
          // An orthonormal basis of the span of the normals kept at the vertex.
          std::vector<Tensor<1, 3>> basis;
          for (const unsigned int k : ks)
            if (!dropped[k])
              {
                Tensor<1, 3> v = nodes[k].n;
                for (const auto &e : basis)
                  v -= (v * e) * e;
                if (v.norm() > 1e-8)
                  basis.push_back(v / v.norm());
              }
          // The keeper of the tangential rows: the first node with friction (only nodes with
          // μ > 0 have tangential rows), else the first.
          unsigned int keeper = numbers::invalid_unsigned_int;
          for (const unsigned int k : ks)
            if (!dropped[k] && (keeper == numbers::invalid_unsigned_int ||
                                (nodes[keeper].friction == 0 && nodes[k].friction > 0)))
              keeper = k;
          for (const unsigned int k : ks)
            {
              if (dropped[k])
                continue;
              ContactNode &node = nodes[k];
              if (k != keeper || basis.size() == 3)
                node.t1 = node.t2 = Tensor<1, 3>();
              else if (basis.size() == 2)
                {
                  node.t1 = cross_product_3d(basis[0], basis[1]);
                  node.t1 /= node.t1.norm();
                  node.t2 = Tensor<1, 3>();
                }
              // The keeper's rows carry this node's friction only if they act on the same
              // motion: both on a rigid obstacle, or both against the same master vertex.
              if (k != keeper && basis.size() < 3 && node.master == nodes[keeper].master)
                node.keeper = keeper;
            }
        }
      std::vector<unsigned int> new_index(nodes.size(), numbers::invalid_unsigned_int);
      unsigned int              kept = 0;
      for (unsigned int k = 0; k < nodes.size(); ++k)
        if (!dropped[k])
          {
            new_index[k]  = kept;
            nodes[kept++] = nodes[k];
          }
      nodes.resize(kept);
      for (auto &node : nodes)
        if (node.keeper)
          node.keeper = new_index[*node.keeper];
    }
  } // namespace

  namespace
  {
    /**
     * The text that tells how deep a node may start inside: the touching depth at vertex @p v of
     * @p slave and the local mesh size it is relative to.
     */
    std::string
    touching_text(const Surface &slave, const unsigned int v)
    {
      return InputParsing::number_text(slave.touching_depth(v)) + " (" +
             InputParsing::number_text(touching_fraction) + " of the local mesh size " +
             InputParsing::number_text(slave.local_edge(v)) + ")";
    }

    /**
     * The gap and normal of @p node towards a rigid plane: χ(x) is its orthogonal projection. A
     * node less than the touching depth behind the plane touches it (gap 0; counted in
     * @p n_touching); deeper it is refused.
     */
    void
    place_on_plane(ContactNode                   &node,
                   const Parameters::ContactZone &zone,
                   const Surface                 &slave,
                   const std::string             &where,
                   unsigned int                  &n_touching)
    {
      // χ(x): the orthogonal projection of x on the plane, so the critical direction
      // is the plane's normal (towards the obstacle) for every node.
      const auto [distance, direction] = obstacle_distance(zone, node.x);
      require(distance >= -slave.touching_depth(node.vertex),
              where + "the node at " + point_text(node.x) +
                " lies inside the rigid obstacle (initial penetration " +
                InputParsing::number_text(-distance) + ", more than " +
                touching_text(slave, node.vertex) + ").");
      n_touching += distance < 0 ? 1 : 0;
      node.gap = std::max(distance, 0.0);
      node.n   = direction;
    }

    /**
     * The gap and normal of @p node towards a rigid sphere or cylinder: χ(x) is the closest point
     * of its surface. Returns false for a node farther than the zone's search distance (not a
     * contact node). A node less than the touching depth inside touches the obstacle (gap 0;
     * counted in @p n_touching); deeper it keeps its negative gap if the search distance admits
     * it, and is refused otherwise.
     */
    bool
    place_on_curved_obstacle(ContactNode                   &node,
                             const Parameters::ContactZone &zone,
                             const Surface                 &slave,
                             const std::string             &where,
                             unsigned int                  &n_touching)
    {
      const auto [distance, direction] = obstacle_distance(zone, node.x);
      const double touching            = slave.touching_depth(node.vertex);
      require(distance >= -std::max(zone.search_distance.value_or(0), touching),
              where + "the node at " + point_text(node.x) + " lies inside the " +
                zone.obstacle->name() + " (initial penetration " +
                InputParsing::number_text(-distance) + ", " +
                (zone.search_distance ? "more than the search distance " +
                                          InputParsing::number_text(*zone.search_distance) + ")." :
                                        "more than " + touching_text(slave, node.vertex) +
                                          ", and no 'Search distance' that admits it)."));
      require(direction.norm() > 0,
              where + "the node at " + point_text(node.x) +
                " lies on the axis or at the centre of the rigid obstacle.");
      if (zone.search_distance && distance > *zone.search_distance)
        return false;
      n_touching += distance < 0 && distance >= -touching ? 1 : 0;
      node.gap = distance >= -touching ? std::max(distance, 0.0) : distance;
      node.n   = direction;
      return true;
    }

    /**
     * The master vertex of @p master opposite @p x along the unit vector @p outer: of the
     * vertices within @p tolerance of the line through @p x along @p outer, the nearest to @p x
     * (the lowest vertex number of equally near ones); without any, the vertex nearest to the
     * line. Returns the vertex (invalid for a surface without vertices), its distance from the
     * line and its distance from @p x.
     */
    std::tuple<unsigned int, double, double>
    opposite_master_vertex(const Point<3>     &x,
                           const Tensor<1, 3> &outer,
                           const Surface      &master,
                           const double        tolerance)
    {
      unsigned int best        = numbers::invalid_unsigned_int;
      double       best_offset = std::numeric_limits<double>::max(),
             best_distance     = std::numeric_limits<double>::max();
      for (const auto &[mv, data] : master.vertex)
        {
          const Tensor<1, 3> d        = data.x - x;
          const double       offset   = (d - (d * outer) * outer).norm();
          const double       distance = d.norm();
          const bool         on_line = offset <= tolerance, best_on_line = best_offset <= tolerance;
          if (on_line ? (!best_on_line || distance < best_distance) :
                        (!best_on_line && offset < best_offset))
            {
              best          = mv;
              best_offset   = offset;
              best_distance = distance;
            }
        }
      return {best, best_offset, best_distance};
    }

    /**
     * The gap and normal of @p node towards the master surface: χ(x) is the master vertex
     * opposite x along its outer normal @p outer (@p partner if given, else
     * opposite_master_vertex()); the meshes must match node to node.
     */
    void
    place_opposite_master(ContactNode                       &node,
                          const Tensor<1, 3>                &outer,
                          const Surface                     &slave,
                          const Surface                     &master,
                          const Body                        &body,
                          const Body                        *master_body,
                          const Parameters::ContactZone     &zone,
                          const std::string                 &where,
                          unsigned int                      &n_touching,
                          const std::optional<unsigned int> &partner = {})
    {
      // χ(x): the master vertex opposite x along the outer normal.
      unsigned int best;
      double       best_offset;
      if (partner)
        {
          best                 = *partner;
          const Tensor<1, 3> d = master.vertex.at(best).x - node.x;
          best_offset          = (d - (d * outer) * outer).norm();
        }
      else
        std::tie(best, best_offset, std::ignore) =
          opposite_master_vertex(node.x, outer, master, 1e-6 * slave.mean_edge);
      require(best != numbers::invalid_unsigned_int && best_offset <= 1e-6 * slave.mean_edge,
              where + "the node at " + point_text(node.x) + " of body '" + body.parameters.name +
                "' has no node of the master surface of body '" + master_body->parameters.name +
                "' opposite it: the meshes of the two surfaces do not match (they must "
                "be conforming node to node).");
      const SurfaceVertex &y = master.vertex.at(best);
      node.master            = {{zone.master_body, best, 1.0, y.x, y.copies}};
      const Tensor<1, 3> d   = y.x - node.x;
      const Tensor<1, 3> master_outer =
        master.normal_sum.at(best) / master.normal_sum.at(best).norm();
      require(master_outer * outer < 0,
              where + "the master surface <" + zone.master_surface.name() + "> of body '" +
                master_body->parameters.name +
                "' faces away from the slave surface: at the node at " + point_text(node.x) +
                " of body '" + body.parameters.name +
                "' the outer normals of the two surfaces are " + point_text(outer) + " and " +
                point_text(master_outer) +
                " (they must point towards each other; is the master surface the "
                "other side of its body?).");
      const double touching = slave.touching_depth(node.vertex);
      require(d * outer >= -touching,
              where + "the node at " + point_text(node.x) + " of body '" + body.parameters.name +
                "' lies inside body '" + master_body->parameters.name + "' (initial penetration " +
                InputParsing::number_text(-(d * outer)) + " along its outer normal, more than " +
                touching_text(slave, node.vertex) + "): the bodies overlap before any load.");
      // Less than the touching depth inside: the node touches the master vertex.
      n_touching += d * outer < 0 ? 1 : 0;
      if (d * outer >= 0 && d.norm() > touching)
        {
          node.n   = d / d.norm();
          node.gap = d.norm();
        }
      else
        {
          node.n   = outer;
          node.gap = 0;
        }
    }

    /**
     * A Dirichlet vertex (@p prescribed components) stays a contact node only under a roller
     * condition tangential to the contact surface; returns false otherwise.
     */
    bool
    orient_for_roller(ContactNode &node, const Body::Prescribed &prescribed)
    {
      // A Dirichlet node is not a contact node, unless its prescribed components are
      // orthogonal to the normal: a symmetry (roller) condition tangential to the contact
      // surface, as on the symmetry planes of a quarter or half model. With friction the
      // tangent t2 is then the prescribed axis: its row acts on no free DoF (contact rows
      // skip the slave's prescribed components, and on the master side the components along
      // them), λ_T2 stays 0, and the disc ‖λ_T‖ ≤ g becomes the
      // interval |λ_T1| ≤ g along the free tangent t1 (the symmetric solution has no
      // tangential force across the symmetry plane).
      bool         conflicts = false;
      unsigned int axis      = numbers::invalid_unsigned_int;
      for (unsigned int d = 0; d < 3; ++d)
        if (prescribed[d])
          {
            if (std::abs(node.n[d]) > 1e-12)
              conflicts = true;
            axis = d;
          }
      if (conflicts)
        return false;
      if (axis != numbers::invalid_unsigned_int)
        {
          Tensor<1, 3> e;
          e[axis] = 1;
          node.t2 = e - (e * node.n) * node.n;
          node.t2 /= node.t2.norm();
          node.t1 = cross_product_3d(node.t2, node.n);
        }
      return true;
    }
  } // namespace

  namespace
  {
    /** The slave side of a zone: its body, its surface and the start of every node. */
    struct ZoneSide
    {
      unsigned int                   z;
      const Parameters::ContactZone &zone;
      const Body                    &body;
      const Surface                 &slave;
      std::string                    where;
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
      start_node(const unsigned int vertex) const
      {
        const SurfaceVertex &x = slave.vertex.at(vertex);
        if (!x.home || (x.copies.prescribed[0] && x.copies.prescribed[1] && x.copies.prescribed[2]))
          return {};
        ContactNode node;
        node.zone          = z;
        node.body          = zone.body;
        node.vertex        = vertex;
        node.x             = x.x;
        node.copies        = x.copies;
        node.friction      = zone.friction_coefficient;
        node.area          = slave.area.at(vertex);
        node.pressure_area = node.area;
        return node;
      }

      /**
       * Completes @p node with its tangents and appends it to @p nodes, unless a prescribed
       * component acts along its normal.
       */
      void
      finish_node(ContactNode &node, std::vector<ContactNode> &nodes) const
      {
        const Body::Prescribed &prescribed = node.copies.prescribed;
        // A node of a body pair on a symmetry plane (a roller condition): the mean normal of its
        // triangles, of which the model has only those on one side of the plane, is turned into
        // the plane, as the mirrored triangles would turn it.
        if (node.on_body())
          {
            Tensor<1, 3> n = node.n;
            for (unsigned int d = 0; d < 3; ++d)
              if (prescribed[d])
                n[d] = 0;
            if (n != node.n && n.norm() > 1e-3)
              node.n = n / n.norm();
          }
        std::tie(node.t1, node.t2) = tangent_basis(node.n);
        if (!orient_for_roller(node, prescribed))
          return;
        nodes.push_back(node);
      }
    };

    /** The surface of a zone as the mortar coupling needs it, and the vertex numbers. */
    struct MortarSurface
    {
      Mortar::Surface                    surface;
      std::vector<unsigned int>          vertex; ///< local → mesh vertex
      std::vector<const SurfaceVertex *> data;   ///< local → its position and copies
    };

    MortarSurface
    mortar_surface(const Surface &s)
    {
      MortarSurface                        m;
      std::map<unsigned int, unsigned int> local;
      for (const auto &[v, data] : s.vertex)
        {
          local[v] = m.vertex.size();
          m.vertex.push_back(v);
          m.data.push_back(&data);
          m.surface.points.push_back(data.x);
        }
      for (const auto &t : s.triangles)
        m.surface.triangles.push_back({{local[t[0]], local[t[1]], local[t[2]]}});
      Mortar::compute_normals(m.surface, s.outward);
      return m;
    }

    /**
     * The master vertex of each home vertex of the slave surface if the coupling is that of
     * matching meshes (every slave vertex fully covered, and M_kj = D_kk for one master vertex j
     * and 0 for the others, on every rank of @p comm); nothing otherwise. Collective.
     */
    std::optional<std::map<unsigned int, unsigned int>>
    matching_partners(const std::vector<Mortar::NodeCoupling> &couplings,
                      const MortarSurface                     &slave,
                      const MortarSurface                     &master,
                      const MPI_Comm                           comm)
    {
      std::map<unsigned int, unsigned int> partner;
      const auto                           match = [&]() {
        for (unsigned int k = 0; k < couplings.size(); ++k)
          {
            if (!slave.data[k]->home)
              continue;
            const auto &c = couplings[k];
            if (c.covered <= 0 || !c.dual)
              return false;
            std::optional<unsigned int> one;
            for (const auto &[j, m] : c.M)
              if (std::abs(m / c.D - 1) <= 1e-8 && !one)
                one = j;
              else if (std::abs(m / c.D) > 1e-8)
                return false;
            if (!one)
              return false;
            partner[slave.vertex[k]] = master.vertex[*one];
          }
        return true;
      };
      const bool matches = match();
      if (Utilities::MPI::min(matches ? 1u : 0u, comm) == 0)
        return {};
      return partner;
    }

    /**
     * Refuses a mortar coupling that found nothing to couple, or an overlap of the bodies deeper
     * than the search distance. If nothing was coupled, a second coupling without a distance
     * limit tells why: surfaces facing away from each other, surfaces that do not overlap at
     * all, or a nearest master triangle beyond the search distance (in front or behind).
     */
    void
    check_mortar_coupling(const ZoneSide           &side,
                          const Body               &master_body,
                          const MortarSurface      &slave,
                          const MortarSurface      &master,
                          const Mortar::Statistics &statistics,
                          const double              distance)
    {
      const std::string pair = "the surface <" + side.zone.surface.name() + "> of body '" +
                               side.body.parameters.name + "' and the master surface <" +
                               side.zone.master_surface.name() + "> of body '" +
                               master_body.parameters.name + "'";
      const std::string overlap = side.where + "body '" + side.body.parameters.name +
                                  "' penetrates body '" + master_body.parameters.name + "' by ";
      const auto refuse_overlap = [&](const Mortar::Statistics &found) {
        throw InputError(overlap + InputParsing::number_text(-found.min_distance) + " m near " +
                         point_text(found.deepest_point) +
                         " before any load, more than the search distance " +
                         InputParsing::number_text(distance) +
                         " m: the bodies overlap (move them apart, or a larger 'Search "
                         "distance').");
      };
      if (statistics.n_segments > 0)
        {
          if (statistics.min_distance < -distance)
            refuse_overlap(statistics);
          return;
        }
      std::vector<Point<3>> all = slave.surface.points;
      all.insert(all.end(), master.surface.points.begin(), master.surface.points.end());
      const BoundingBox<3> box(all);
      Mortar::Statistics   wide;
      Mortar::couple(slave.surface,
                     master.surface,
                     box.side_length(0) + box.side_length(1) + box.side_length(2),
                     wide);
      require(wide.n_segments > 0 || wide.n_facing_away == 0,
              side.where + pair +
                " face away from each other: where they overlap, their outer normals point "
                "the same way (they must point towards each other; is the master surface the "
                "other side of its body?).");
      require(wide.n_segments > 0,
              side.where + pair +
                " do not overlap: no master triangle lies opposite a slave triangle (the right "
                "surfaces?).");
      if (wide.min_distance < 0)
        refuse_overlap(wide);
      throw InputError(side.where + pair + " are too far apart: the nearest master triangle lies " +
                       InputParsing::number_text(wide.min_distance) +
                       " m in front of the slave surface, beyond the search distance " +
                       InputParsing::number_text(distance) +
                       " m (a larger 'Search distance', if the gap may close).");
    }

    /** The mortar nodes of a zone from the coupling of its surfaces. */
    void
    add_mortar_nodes(const ZoneSide                          &side,
                     const std::vector<Mortar::NodeCoupling> &couplings,
                     const MortarSurface                     &slave,
                     const MortarSurface                     &master,
                     std::vector<ContactNode>                &nodes,
                     ZoneReport                              &report)
    {
      for (unsigned int k = 0; k < couplings.size(); ++k)
        {
          auto node = side.start_node(slave.vertex[k]);
          if (!node)
            continue;
          const auto &c = couplings[k];
          if (c.covered <= 0)
            {
              ++report.n_uncovered;
              continue;
            }
          node->n   = c.normal;
          node->gap = c.weighted_gap / c.D;
          // Less than the touching depth inside the master body: the node touches it.
          if (node->gap < 0 && node->gap >= -side.slave.touching_depth(node->vertex))
            {
              node->gap = 0;
              ++report.n_touching;
            }
          node->pressure_area = c.D;
          node->mortar        = true;
          for (const auto &[j, m] : c.M)
            node->master.push_back({side.zone.master_body,
                                    master.vertex[j],
                                    m / c.D,
                                    master.data[j]->x,
                                    master.data[j]->copies});
          report.n_partly_covered += c.dual ? 0 : 1;
          report.n_overlapping += node->gap < 0 ? 1 : 0;
          side.finish_node(*node, nodes);
        }
    }

    /** Replaces each of @p counts by its sum over the ranks of @p comm. Collective. */
    void
    add_over_ranks(const std::vector<unsigned int *> &counts, const MPI_Comm comm)
    {
      std::vector<unsigned int> values;
      for (const unsigned int *count : counts)
        values.push_back(*count);
      Utilities::MPI::sum(values, comm, values);
      for (unsigned int i = 0; i < counts.size(); ++i)
        *counts[i] = values[i];
    }

    /**
     * Runs @p local_work, which may throw InputError; if it throws on any rank of @p comm, the
     * message of the lowest such rank is thrown on every rank. Collective.
     */
    void
    collectively(const MPI_Comm comm, const std::function<void()> &local_work)
    {
      std::string error;
      try
        {
          local_work();
        }
      catch (const InputError &e)
        {
          error = e.what();
        }
      error = MPITools::first_error(comm, error);
      if (!error.empty())
        throw InputError(error);
    }

    /** The bounding box of the vertices of the triangles of @p s this rank holds. */
    Regions::Region
    box_of_own(const Surface &s)
    {
      std::vector<Point<3>> points;
      for (unsigned int t = 0; t < s.triangles.size(); ++t)
        if (s.own[t])
          for (const unsigned int v : s.triangles[t])
            points.push_back(s.vertex.at(v).x);
      return Regions::box_of(points);
    }

    /** The bounding box of all vertices of @p s, or nothing. */
    Regions::Region
    box_of_all(const Surface &s)
    {
      std::vector<Point<3>> points;
      for (const auto &[v, data] : s.vertex)
        points.push_back(data.x);
      return Regions::box_of(points);
    }

    /**
     * The sum of the side lengths of the bounding box of the slave faces and the master faces
     * @p master_own of all ranks (how far behind a slave triangle to look for an overlap, and
     * the largest distance between the surfaces). Collective.
     */
    double
    span_of_both(const ZoneSide &side, const std::vector<SurfaceFace> &master_own)
    {
      Regions::Region both = box_of_own(side.slave);
      if (const auto m = box_of(master_own))
        Regions::merge(both, *m);
      both = Regions::union_over_ranks(side.comm, both);
      return both ? both->side_length(0) + both->side_length(1) + both->side_length(2) : 0;
    }

    /**
     * The statistics of the coupling of every rank's share: the counts added, the smallest
     * distance and the point of the lowest rank where it occurs. Collective.
     */
    void
    sum_over_ranks(Mortar::Statistics &statistics, const MPI_Comm comm)
    {
      add_over_ranks(
        {&statistics.n_candidate_pairs, &statistics.n_segments, &statistics.n_facing_away}, comm);
      const double       least = Utilities::MPI::min(statistics.min_distance, comm);
      const unsigned int rank  = Utilities::MPI::this_mpi_process(comm);
      const unsigned int holder =
        Utilities::MPI::min(statistics.min_distance == least ? rank : numbers::invalid_unsigned_int,
                            comm);
      statistics.min_distance  = least;
      statistics.deepest_point = Utilities::MPI::broadcast(comm, statistics.deepest_point, holder);
    }

    /**
     * The master surface of a body-pair zone as a rank needs it: all of it, or (the search
     * shared) the master faces near this rank's slave faces.
     */
    class MasterSurface
    {
    public:
      MasterSurface(const ZoneSide &side, const Body &body, const BoundarySelector &selector)
        : side(side)
        , body(body)
        , selector(selector)
      {
        if (side.shared())
          own = own_faces(body, selector, side.parts_of_vertex(body));
        else
          surface = collect_surface(body, selector, side.parts_of_vertex(body), Share::whole);
      }

      /**
       * Adds the master faces within @p margin of the region of every rank, @p region this
       * rank's (shared search; nothing otherwise). Collective.
       */
      void
      add_faces_near(const Regions::Region &region, const double margin)
      {
        if (!side.shared())
          return;
        std::vector<SurfaceFace> added =
          faces_in_regions(body, own, Regions::of_ranks(side.comm, region), margin);
        near.insert(near.end(), added.begin(), added.end());
        near    = exchange_faces(body, std::move(near), {});
        surface = surface_of(near, 0, [](const SurfaceFace &, unsigned int) { return true; });
      }

      /** Appends the master triangles this rank holds to @p list (Surface::append_to()). */
      void
      append_own_to(std::vector<ContactTriangle> &list,
                    const unsigned int            zone,
                    const unsigned int            body_index) const
      {
        if (side.shared())
          surface_of(own, 0, [](const SurfaceFace &, unsigned int) {
            return true;
          }).append_to(list, zone, body_index);
        else
          surface.append_to(list, zone, body_index);
      }

      /** The whole master surface (gathered if the search is shared). Collective. */
      Surface
      whole() const
      {
        return side.shared() ?
                 collect_surface(body, selector, side.parts_of_vertex(body), Share::whole) :
                 surface;
      }

      const ZoneSide         &side;
      const Body             &body;
      const BoundarySelector &selector;
      /** The faces this rank holds (shared search). */
      std::vector<SurfaceFace> own;
      /** The faces near this rank's slave faces (shared search). */
      std::vector<SurfaceFace> near;
      Surface                  surface;
    };

    /**
     * The mortar coupling of a zone's surfaces, with the statistics of all ranks. A shared
     * search couples this rank's slave faces with the master faces near them (within the search
     * distance, and behind the slave triangles without a segment), which gives the home
     * vertices' couplings of the whole surfaces.
     */
    std::vector<Mortar::NodeCoupling>
    couple_surfaces(const ZoneSide     &side,
                    MasterSurface      &master,
                    const double        distance,
                    MortarSurface      &slave_m,
                    MortarSurface      &master_m,
                    Mortar::Statistics &statistics)
    {
      slave_m = mortar_surface(side.slave);
      Mortar::Share share;
      if (side.shared())
        {
          master.add_faces_near(box_of_all(side.slave), distance);
          share.counted.assign(side.slave.own.begin(), side.slave.own.end());
          share.depth = span_of_both(side, master.own);
        }
      master_m = mortar_surface(master.surface);
      auto couplings =
        Mortar::couple(slave_m.surface, master_m.surface, distance, statistics, share);
      if (side.shared())
        {
          // A master surface deep behind a slave triangle without a segment: the faces there too.
          if (Utilities::MPI::logical_or(statistics.searched_behind.has_value(), side.comm))
            {
              master.add_faces_near(statistics.searched_behind, 0);
              master_m = mortar_surface(master.surface);
              couplings =
                Mortar::couple(slave_m.surface, master_m.surface, distance, statistics, share);
            }
          sum_over_ranks(statistics, side.comm);
        }
      return couplings;
    }

    /**
     * A shared search of a zone discretized node to node: the master faces within a distance of
     * this rank's slave faces that grows (×8, from the mean edge) until every rank finds a master
     * vertex opposite each of its home vertices, or the distance spans both surfaces (then
     * place_opposite_master() tells which node has none). Collective.
     */
    void
    add_master_faces_opposite(const ZoneSide &side, MasterSurface &master)
    {
      const double span   = span_of_both(side, master.own);
      const auto   region = box_of_all(side.slave);
      for (double reach = side.slave.mean_edge;; reach *= 8)
        {
          master.add_faces_near(region, std::min(reach, span));
          // Found: a vertex opposite every home node, and every master vertex nearer to the
          // node than it in the window (its ball lies in the window), so that the nearest one
          // is that of the whole surface.
          bool missing = false;
          for (const auto &[vertex, normal_sum] : side.slave.normal_sum)
            if (side.start_node(vertex))
              {
                const auto [best, offset, distance] =
                  opposite_master_vertex(side.slave.vertex.at(vertex).x,
                                         normal_sum / normal_sum.norm(),
                                         master.surface,
                                         1e-6 * side.slave.mean_edge);
                missing |= offset > 1e-6 * side.slave.mean_edge || distance > reach;
              }
          if (!Utilities::MPI::logical_or(missing, side.comm) || reach >= span)
            return;
        }
    }

    /**
     * Appends the home vertices of the slave surface of @p side that are no node of the zone
     * (its nodes are those of @p nodes from @p first) to @p uncoupled.
     */
    void
    add_uncoupled_vertices(const ZoneSide                       &side,
                           const std::vector<ContactNode>       &nodes,
                           const unsigned int                    first,
                           std::vector<ContactSurfaces::Vertex> &uncoupled)
    {
      std::set<unsigned int> coupled;
      for (unsigned int k = first; k < nodes.size(); ++k)
        coupled.insert(nodes[k].vertex);
      for (const auto &[vertex, data] : side.slave.vertex)
        if (data.home && coupled.count(vertex) == 0)
          uncoupled.push_back({side.z, side.zone.body, vertex, data.x, data.copies.parts.front()});
    }

    /** The nodes of a body-pair zone, node to node or mortar. */
    void
    add_body_pair_nodes(const ZoneSide                           &side,
                        const std::vector<std::unique_ptr<Body>> &bodies,
                        std::vector<ContactNode>                 &nodes,
                        ZoneReport                               &report)
    {
      using Discretization         = Parameters::ContactZone::Discretization;
      const auto      &zone        = side.zone;
      const Body      &master_body = *bodies[zone.master_body];
      BoundarySelector master_selector(zone.master_surface);
      try
        {
          master_selector.resolve(master_body.mesh,
                                  master_body.parameters.name,
                                  master_body.mesh_comm(),
                                  master_body.parameters.mesh.transform);
        }
      catch (const InputError &e)
        {
          throw InputError(side.where + "Master surface: " + e.what());
        }
      MasterSurface master(side, master_body, master_selector);

      std::optional<std::map<unsigned int, unsigned int>> partner;
      if (zone.discretization != Discretization::node_to_node)
        {
          report.search_distance = zone.search_distance.value_or(side.slave.mean_edge);
          MortarSurface      slave_m, master_m;
          Mortar::Statistics statistics;
          const auto         couplings =
            couple_surfaces(side, master, report.search_distance, slave_m, master_m, statistics);
          report.n_segments = statistics.n_segments;
          if (statistics.n_segments == 0 && side.shared())
            check_mortar_coupling(side,
                                  master_body,
                                  mortar_surface(collect_surface(side.body,
                                                                 side.selector,
                                                                 side.parts_of_vertex(side.body),
                                                                 Share::whole)),
                                  mortar_surface(master.whole()),
                                  statistics,
                                  report.search_distance);
          else
            check_mortar_coupling(
              side, master_body, slave_m, master_m, statistics, report.search_distance);
          if (zone.discretization == Discretization::automatic)
            partner = matching_partners(couplings, slave_m, master_m, side.comm);
          if (!partner)
            {
              report.discretization = "mortar";
              collectively(side.comm, [&]() {
                add_mortar_nodes(side, couplings, slave_m, master_m, nodes, report);
              });
              if (side.surfaces != nullptr)
                master.append_own_to(side.surfaces->master, side.z, zone.master_body);
              return;
            }
        }
      else if (side.shared())
        add_master_faces_opposite(side, master);
      if (side.surfaces != nullptr)
        master.append_own_to(side.surfaces->master, side.z, zone.master_body);
      report.discretization = "node to node";
      collectively(side.comm, [&]() {
        for (const auto &[vertex, normal_sum] : side.slave.normal_sum)
          if (auto node = side.start_node(vertex))
            {
              std::optional<unsigned int> hint;
              if (partner && partner->count(vertex) > 0)
                hint = partner->at(vertex);
              place_opposite_master(*node,
                                    normal_sum / normal_sum.norm(),
                                    side.slave,
                                    master.surface,
                                    side.body,
                                    &master_body,
                                    zone,
                                    side.where,
                                    report.n_touching,
                                    hint);
              side.finish_node(*node, nodes);
            }
      });
    }
  } // namespace

  std::vector<ContactNode>
  find_contact_nodes(const std::vector<std::unique_ptr<Body>> &bodies,
                     const Parameters::Contact                &contact,
                     ContactSurfaces                          *surfaces,
                     std::vector<ZoneReport>                  *reports,
                     const bool                                home_nodes)
  {
    std::vector<std::vector<std::vector<unsigned int>>> parts(bodies.size());
    const std::function<const std::vector<std::vector<unsigned int>> &(const Body &)>
      parts_of_vertex = [&](const Body &body) -> const std::vector<std::vector<unsigned int>> & {
      if (parts[body.index].empty())
        parts[body.index] = body.parts_of_mesh_vertices();
      return parts[body.index];
    };
    // Shared: every rank finds the nodes of its home vertices (the bodies' cells distributed).
    const bool     shared = home_nodes && !bodies.empty() && bodies.front()->distributed();
    const MPI_Comm comm   = shared ? bodies.front()->mesh_comm() : MPI_COMM_SELF;
    std::vector<ContactNode> nodes;
    for (unsigned int z = 0; z < contact.zones.size(); ++z)
      {
        const auto       &zone  = contact.zones[z];
        const std::string where = "Contact zone " + std::to_string(z + 1) + ": ";
        const Body       &body  = *bodies[zone.body];
        BoundarySelector  surface(zone.surface);
        try
          {
            surface.resolve(body.mesh,
                            body.parameters.name,
                            body.mesh_comm(),
                            body.parameters.mesh.transform);
          }
        catch (const InputError &e)
          {
            throw InputError(where + "Surface: " + e.what());
          }
        const Share   share = shared ? Share::home_rings : Share::whole;
        const Surface slave = collect_surface(body, surface, parts_of_vertex(body), share);
        if (surfaces != nullptr)
          slave.append_to(surfaces->slave, z, zone.body);

        const ZoneSide side{
          z, zone, body, slave, where, surfaces, parts_of_vertex, surface, share, comm};
        ZoneReport         report;
        const unsigned int first = nodes.size();
        if (zone.rigid() && zone.obstacle->half_space_normal())
          {
            report.discretization = "rigid plane";
            check_plane_faces_body(slave, body, zone, where, comm);
            collectively(comm, [&]() {
              for (const auto &[vertex, normal_sum] : slave.normal_sum)
                if (auto node = side.start_node(vertex))
                  {
                    place_on_plane(*node, zone, slave, where, report.n_touching);
                    side.finish_node(*node, nodes);
                  }
            });
          }
        else if (zone.rigid())
          {
            report.discretization  = "rigid obstacle";
            report.search_distance = zone.search_distance.value_or(0);
            collectively(comm, [&]() {
              for (const auto &[vertex, normal_sum] : slave.normal_sum)
                if (auto node = side.start_node(vertex))
                  {
                    if (!place_on_curved_obstacle(*node, zone, slave, where, report.n_touching))
                      {
                        ++report.n_uncovered;
                        continue;
                      }
                    report.n_overlapping += node->gap < 0 ? 1 : 0;
                    side.finish_node(*node, nodes);
                  }
            });
          }
        else
          {
            add_body_pair_nodes(side, bodies, nodes, report);
            if (surfaces != nullptr)
              add_uncoupled_vertices(side, nodes, first, surfaces->uncoupled);
          }
        report.n_nodes = nodes.size() - first;
        add_over_ranks({&report.n_nodes,
                        &report.n_uncovered,
                        &report.n_partly_covered,
                        &report.n_overlapping,
                        &report.n_touching},
                       comm);
        require(report.n_nodes > 0,
                where + "the surface <" + zone.surface.name() + "> of body '" +
                  body.parameters.name +
                  "' has no contact node (all its vertices are Dirichlet vertices" +
                  (report.n_uncovered > 0 ? ", or have no master surface opposite them)." : ")."));
        if (reports != nullptr)
          reports->push_back(report);
      }
    combine_shared_vertices(nodes);
    return nodes;
  }

  Tensor<1, 3>
  relative_displacement(const ContactNode &node, const VertexDisplacements &u)
  {
    Tensor<1, 3> relative = u(node.body, node.vertex);
    for (const auto &m : node.master)
      relative -= m.weight * u(m.body, m.vertex);
    return relative;
  }

  Point<3>
  master_point(const ContactNode &node)
  {
    Point<3> y;
    for (const auto &m : node.master)
      y += m.weight * m.y;
    return y;
  }

  std::vector<double>
  slip_bounds(const std::vector<ContactNode> &nodes, const std::vector<double> &normal_force)
  {
    std::vector<double> g(nodes.size());
    for (unsigned int k = 0; k < nodes.size(); ++k)
      g[k] = nodes[k].friction * std::max(normal_force[k], 0.0);
    for (unsigned int k = 0; k < nodes.size(); ++k)
      if (nodes[k].keeper)
        g[*nodes[k].keeper] += g[k];
    return g;
  }

  std::size_t
  memory_consumption(const std::vector<ContactNode> &nodes, const ContactSurfaces &surfaces)
  {
    std::size_t bytes =
      nodes.capacity() * sizeof(ContactNode) +
      (surfaces.slave.capacity() + surfaces.master.capacity()) * sizeof(ContactTriangle) +
      surfaces.uncoupled.capacity() * sizeof(ContactSurfaces::Vertex);
    for (const ContactNode &node : nodes)
      {
        bytes += node.master.capacity() * sizeof(MasterPoint) +
                 node.copies.parts.capacity() * sizeof(unsigned int);
        for (const MasterPoint &m : node.master)
          bytes += m.copies.parts.capacity() * sizeof(unsigned int);
      }
    return bytes;
  }
} // namespace FetiContact
