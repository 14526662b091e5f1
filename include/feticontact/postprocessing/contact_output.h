#pragma once

#include <feticontact/base/output_files.h>
#include <feticontact/contact/contact_geometry.h>
#include <feticontact/contact/contact_results.h>

#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * Writes the contact surfaces for ParaView: `contact_surface.vtu` (the triangles of every
   * zone's slave surface, with per-vertex data: the normal force λ_N, the contact force on the
   * body as a vector −(λ_N n + λ_T1 t1 + λ_T2 t2), the tangential part of it, the gap d − N u, the
   * slip vector (T1 u) t1 + (T2 u) t2, the status 0 open / 1 stick / 2 slip (−1 for surface
   * vertices that are not contact nodes, e.g. Dirichlet vertices), and the zone) and
   * `contact_surface.pvd` pointing to it, into @p directory through @p files.
   */
  void
  write_contact_surface_vtu(ResultFiles                              &files,
                            const std::string                        &directory,
                            const std::vector<std::unique_ptr<Body>> &bodies,
                            const std::vector<ContactNode>           &nodes,
                            const std::vector<ContactNodeResult>     &results,
                            const std::vector<ContactTriangle>       &triangles);
} // namespace FetiContact
