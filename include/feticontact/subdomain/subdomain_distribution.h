#pragma once

#include <deal.II/fe/fe.h>

#include <feticontact/scene/body.h>
#include <feticontact/subdomain/subdomain.h>

#include <memory>
#include <mpi.h>
#include <vector>

namespace FetiContact
{
  /**
   * The subdomains of all bodies over the ranks: subdomain s of the run is part p of body b with
   * s = first_subdomain[b] + p (first_subdomain: per body, and the number of subdomains at the
   * end), and owner[s] is the rank that holds it.
   */
  namespace SubdomainDistribution
  {
    /**
     * The rank of every subdomain: contiguous ranges of subdomains, balanced by their numbers
     * of cells (each rank at most its share plus one subdomain). Every rank computes the same
     * assignment. Collective.
     */
    std::vector<unsigned int>
    owners(const std::vector<std::unique_ptr<Body>> &bodies,
           const std::vector<unsigned int>          &first_subdomain,
           const MPI_Comm                            comm);

    /**
     * The subdomains that @p owner gives to @p rank, their meshes and DoFs, made on the
     * subdomain threads (@p eliminate_prescribed: the primal Dirichlet treatment).
     */
    std::vector<std::unique_ptr<Subdomain>>
    make_subdomains(const std::vector<std::unique_ptr<Body>> &bodies,
                    const std::vector<unsigned int>          &first_subdomain,
                    const std::vector<unsigned int>          &owner,
                    const unsigned int                        rank,
                    const bool                                eliminate_prescribed,
                    const dealii::FiniteElement<3>           &fe);

    /**
     * The first rigid body mode of every one of the @p n_subdomains subdomains, and the number
     * of modes at the end, from the factorized subdomains @p owned of every rank. Collective.
     */
    std::vector<unsigned int>
    mode_offsets(const std::vector<Subdomain *> &owned,
                 const unsigned int              n_subdomains,
                 const MPI_Comm                  comm);
  } // namespace SubdomainDistribution
} // namespace FetiContact
