#include <deal.II/base/bounding_box.h>
#include <deal.II/base/mpi.h>

#include <feticontact/base/exact_sum.h>
#include <feticontact/base/regions.h>
#include <feticontact/contact/contact_surfaces.h>

#include <boost/serialization/array.hpp>
#include <boost/serialization/vector.hpp>
#include <cmath>
#include <limits>
#include <set>

namespace FetiContact::ContactSearch
{
  using namespace dealii;

  namespace
  {
    /** The rank (of the body's mesh_comm()) that finds the nodes of vertex @p v of @p face. */
    unsigned int
    home_rank(const Body &body, const SurfaceFace &face, const unsigned int v)
    {
      return body.rank_of_part(face.holders[v].front());
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
  } // namespace

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

  Regions::Region
  box_of(const std::vector<SurfaceFace> &faces)
  {
    Regions::Region box;
    for (const SurfaceFace &face : faces)
      Regions::merge(box, face.box());
    return box;
  }

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

  Regions::Region
  box_of_all(const Surface &s)
  {
    std::vector<Point<3>> points;
    for (const auto &[v, data] : s.vertex)
      points.push_back(data.x);
    return Regions::box_of(points);
  }
} // namespace FetiContact::ContactSearch
