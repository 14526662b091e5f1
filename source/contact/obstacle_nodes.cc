#include <feticontact/base/exact_sum.h>
#include <feticontact/base/input_parsing.h>
#include <feticontact/base/mpi_tools.h>
#include <feticontact/contact/obstacle_nodes.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace FetiContact::ContactSearch
{
  using namespace dealii;

  namespace
  {
    /**
     * A rigid plane's normal @p plane_normal (RigidObstacle::half_space_normal()) must point out
     * of the obstacle, towards the body: against the (area-weighted) outer normal of the zone's
     * surface. Otherwise InputError names the zone and the node whose outer normal points most
     * along the plane's normal.
     */
    void
    check_plane_faces_body(const Surface                 &slave,
                           const Body                    &body,
                           const Tensor<1, 3>            &plane_normal,
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
            const double c = normal_sum * plane_normal / normal_sum.norm();
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
      const double cosine = total.norm() > 0 ? total * plane_normal / total.norm() : 0;
      require(total.norm() < 0.7 * magnitude || std::abs(cosine) > 0.1,
              where + "the plane normal " + point_text(plane_normal) +
                " is (nearly) perpendicular to the surface <" + zone.surface.name() +
                "> of body '" + body.parameters.name + "', whose mean outer normal is " +
                point_text(total / std::max(total.norm(), 1e-300)) + " (cosine " +
                InputParsing::number_text(cosine) +
                "): a rigid plane must face the surface it is paired with (a plane normal "
                "against that outer normal, or the surface that faces the plane).");
      require(total * plane_normal < 0,
              where + "the plane normal " + point_text(plane_normal) + " points into body '" +
                body.parameters.name + "': the outer normal of its surface <" +
                zone.surface.name() + "> is " + point_text(worst_normal) + " at the node at " +
                point_text(worst_x) +
                ". The plane normal must point out of the obstacle, towards the body (here " +
                point_text(-plane_normal) + "?).");
    }

    /**
     * The gap and normal of @p node towards a rigid plane: χ(x) is its orthogonal projection. A
     * node less than the touching depth behind the plane touches it (gap 0; counted in
     * @p n_touching); deeper it is refused.
     */
    void
    place_on_plane(ContactNode         &node,
                   const RigidObstacle &plane,
                   const Surface       &slave,
                   const std::string   &where,
                   unsigned int        &n_touching)
    {
      // χ(x): the orthogonal projection of x on the plane, so the critical direction
      // is the plane's normal (towards the obstacle) for every node.
      const double distance = plane.signed_distance(node.x);
      require(distance >= -slave.touching_depth(node.vertex),
              where + "the node at " + point_text(node.x) +
                " lies inside the rigid obstacle (initial penetration " +
                InputParsing::number_text(-distance) + ", more than " +
                touching_text(slave, node.vertex) + ").");
      n_touching += distance < 0 ? 1 : 0;
      node.gap = std::max(distance, 0.0);
      node.n   = -plane.outward_normal(node.x);
    }

    /**
     * The gap and normal of @p node towards a curved rigid obstacle (a sphere, a cylinder): χ(x) is
     * the closest point of its surface. Returns false for a node farther than the zone's search
     * distance (not a contact node). A node less than the touching depth inside touches the
     * obstacle (gap 0; counted in @p n_touching); deeper it keeps its negative gap if the search
     * distance admits it, and is refused otherwise.
     */
    bool
    place_on_curved_obstacle(ContactNode                   &node,
                             const RigidObstacle           &obstacle,
                             const Parameters::ContactZone &zone,
                             const Surface                 &slave,
                             const std::string             &where,
                             unsigned int                  &n_touching)
    {
      const double       distance  = obstacle.signed_distance(node.x);
      const Tensor<1, 3> direction = -obstacle.outward_normal(node.x);
      const double       touching  = slave.touching_depth(node.vertex);
      require(distance >= -std::max(zone.search_distance.value_or(0), touching),
              where + "the node at " + point_text(node.x) + " lies inside the " + obstacle.name() +
                " (initial penetration " + InputParsing::number_text(-distance) + ", " +
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
  } // namespace

  void
  add_obstacle_nodes(const ZoneSide           &side,
                     const RigidObstacle      &obstacle,
                     std::vector<ContactNode> &nodes,
                     ZoneReport               &report)
  {
    if (const auto plane_normal = obstacle.half_space_normal())
      {
        report.discretization = "rigid plane";
        check_plane_faces_body(
          side.slave, side.body, *plane_normal, side.zone, side.where, side.comm);
        MPITools::collectively<InputError>(side.comm, [&]() {
          for (const auto &[vertex, normal_sum] : side.slave.normal_sum)
            if (auto node = side.start_node(vertex))
              {
                place_on_plane(*node, obstacle, side.slave, side.where, report.n_touching);
                side.finish_node(*node, nodes);
              }
        });
      }
    else
      {
        report.discretization  = "rigid obstacle";
        report.search_distance = side.zone.search_distance.value_or(0);
        MPITools::collectively<InputError>(side.comm, [&]() {
          for (const auto &[vertex, normal_sum] : side.slave.normal_sum)
            if (auto node = side.start_node(vertex))
              {
                if (!place_on_curved_obstacle(
                      *node, obstacle, side.zone, side.slave, side.where, report.n_touching))
                  {
                    ++report.n_uncovered;
                    continue;
                  }
                report.n_overlapping += node->gap < 0 ? 1 : 0;
                side.finish_node(*node, nodes);
              }
        });
      }
  }
} // namespace FetiContact::ContactSearch
