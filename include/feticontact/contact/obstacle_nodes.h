#pragma once

#include <feticontact/contact/contact_nodes.h>
#include <feticontact/contact/rigid_obstacle.h>

#include <vector>

namespace FetiContact::ContactSearch
{
  /**
   * The contact nodes of the zone of @p side against its rigid obstacle @p obstacle, appended to
   * @p nodes (find_contact_nodes()): χ(x_k) is the point of the obstacle's surface closest to x_k
   * and n_k = −RigidObstacle::outward_normal(x_k), into the obstacle.
   *
   * A half-space (RigidObstacle::half_space_normal(), a rigid plane; report "rigid plane"):
   * every vertex of the surface is a node; the surface must face the plane (else InputError), and
   * a node more than the touching depth behind the plane is refused. A curved obstacle (report
   * "rigid obstacle"): the vertices farther than the zone's search distance are no nodes (counted
   * as uncovered), and a node deeper inside than the touching depth keeps its negative gap if the
   * search distance admits it (counted as overlapping) and is refused otherwise. Nodes less than
   * the touching depth inside touch the obstacle (gap 0). Collective on the ranks of the search.
   */
  void
  add_obstacle_nodes(const ZoneSide           &side,
                     const RigidObstacle      &obstacle,
                     std::vector<ContactNode> &nodes,
                     ZoneReport               &report);
} // namespace FetiContact::ContactSearch
