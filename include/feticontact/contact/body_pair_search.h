#pragma once

#include <feticontact/contact/contact_nodes.h>

#include <memory>
#include <vector>

namespace FetiContact::ContactSearch
{
  /**
   * The part of the boundary of @p body that @p selection names, resolved on the body's mesh
   * (BoundarySelector::resolve()); an InputError gives @p where (the zone and the entry, e.g.
   * "Contact zone 1: Surface: ") before its reason.
   */
  BoundarySelector
  resolved_surface(const Body &body, const BoundarySelector &selection, const std::string &where);

  /**
   * Appends the home vertices of the slave surface of @p side that are no node of the zone
   * (its nodes are those of @p nodes from @p first) to @p uncoupled.
   */
  void
  add_uncoupled_vertices(const ZoneSide                       &side,
                         const std::vector<ContactNode>       &nodes,
                         const unsigned int                    first,
                         std::vector<ContactSurfaces::Vertex> &uncoupled);

  /**
   * The nodes of the body-pair zone of @p side, appended to @p nodes: node to node (χ(x_k) the
   * master vertex opposite x_k) or mortar (doc/contact.md, "Non-matching meshes"), as the
   * zone's Discretization says ('automatic': node to node where the mortar coupling is that of
   * matching meshes). The master triangles this rank holds go to side.surfaces. Collective on
   * the ranks of the search.
   */
  void
  add_body_pair_nodes(const ZoneSide                           &side,
                      const std::vector<std::unique_ptr<Body>> &bodies,
                      std::vector<ContactNode>                 &nodes,
                      ZoneReport                               &report);
} // namespace FetiContact::ContactSearch
