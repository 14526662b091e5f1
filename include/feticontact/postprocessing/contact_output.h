#pragma once

#include <feticontact/base/output_files.h>
#include <feticontact/contact/contact_geometry.h>
#include <feticontact/contact/contact_results.h>
#include <feticontact/subdomain/subdomain.h>

#include <array>
#include <map>
#include <mpi.h>
#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * The contact output's share of one rank: the contact nodes and the triangles of the contact
   * surfaces that belong to the rank's subdomains, by subdomain. A node belongs to the subdomain
   * of lowest number that holds its vertex (the copy whose displacement the output reports), a
   * triangle to the subdomain of the cell whose face it is. The ranks hold contiguous ranges of
   * subdomains in rank order, so output by subdomain in rank order is the same on any number of
   * ranks.
   */
  struct ContactOutputShare
  {
    /** This rank's contact nodes, by subdomain and then in the order of the nodes. */
    std::vector<unsigned int> nodes;
    /** The subdomains of this rank with triangles, increasing, and the triangles of each. */
    std::vector<unsigned int>              subdomains;
    std::vector<std::vector<unsigned int>> triangles;
    /**
     * For every point (zone, body, vertex) of this rank's triangles, the subdomain whose piece
     * holds it as its own: the lowest subdomain with a triangle at the point, on any rank. In the
     * other pieces with the point it is a duplicate (vtkGhostType), so that sums over the whole
     * surface in ParaView count every point once.
     */
    std::map<std::array<unsigned int, 3>, unsigned int> point_owner;

    /**
     * The share of this rank's subdomains @p owned, of the @p nodes and @p triangles it lists
     * (@p subdomain_owner: the rank of every subdomain, of @p comm). Collective.
     */
    ContactOutputShare(const std::vector<unsigned int>    &first_subdomain,
                       const std::vector<Subdomain *>     &owned,
                       const std::vector<ContactNode>     &nodes,
                       const std::vector<ContactTriangle> &triangles,
                       const std::vector<unsigned int>    &subdomain_owner,
                       const MPI_Comm                      comm);

  private:
    /**
     * Lowers every entry of point_owner to the lowest subdomain of all ranks with a triangle at
     * the point: each point's rank of its home subdomain compares the ranks' values. Collective.
     */
    void
    lowest_over_ranks(const std::vector<unsigned int>    &first_subdomain,
                      const std::vector<ContactTriangle> &triangles,
                      const std::vector<unsigned int>    &subdomain_owner,
                      const MPI_Comm                      comm);
  };

  /**
   * Writes contact.csv (write_contact_csv()): every rank the rows of its share's nodes, in rank
   * order, into the one file (ResultFiles::write_collectively()). Collective.
   */
  void
  write_contact_csv(ResultFiles                          &files,
                    const MPI_Comm                        comm,
                    const std::string                    &directory,
                    const ContactOutputShare             &share,
                    const std::vector<ContactNode>       &nodes,
                    const std::vector<ContactNodeResult> &results);

  /**
   * Writes the contact surfaces for ParaView: every rank one piece `contact_surface_NNNN.vtu` per
   * subdomain NNNN of its share (the triangles of that subdomain's faces on the zones' slave
   * surfaces, with per-vertex data: the normal force λ_N, the pressure λ_N / D_kk, the contact
   * force on the body as a vector −(λ_N n + λ_T1 t1 + λ_T2 t2), the tangential part of it, the
   * gap d − N u, the slip vector (T1 u) t1 + (T2 u) t2, the status 0 open / 1 stick / 2 slip (−1
   * for surface vertices that are not contact nodes, e.g. Dirichlet vertices), the zone and D_kk;
   * vtkGhostType marks a point that another piece holds as its own, ContactOutputShare::
   * point_owner), and rank 0 the records `contact_surface.pvtu` (the pieces of all ranks) and
   * `contact_surface.pvd` pointing to it, into @p directory through @p files. Collective.
   *
   * @p nodes are this rank's contact nodes. If they are split among the ranks of @p node_comm
   * (else MPI_COMM_SELF), each on the rank of its home subdomain (@p subdomain_owner of
   * @p first_subdomain of its body plus ContactTriangle::home), the values of a piece's points
   * whose nodes another rank holds are asked of that rank, point to point.
   */
  void
  write_contact_surface_vtu(ResultFiles                          &files,
                            const MPI_Comm                        comm,
                            const std::string                    &directory,
                            const ContactOutputShare             &share,
                            const std::vector<ContactNode>       &nodes,
                            const std::vector<ContactNodeResult> &results,
                            const std::vector<ContactTriangle>   &triangles,
                            const std::vector<unsigned int>      &first_subdomain,
                            const std::vector<unsigned int>      &subdomain_owner,
                            const MPI_Comm                        node_comm);
} // namespace FetiContact
