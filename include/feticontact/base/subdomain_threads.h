#pragma once

#include <functional>
#include <mpi.h>

namespace FetiContact::SubdomainThreads
{
  /**
   * Starts the threads of this rank for the subdomains' local work: one per core that the rank
   * may run on (its CPU affinity, which mpirun's binding sets) divided by the number of ranks on
   * the machine, at least one; the environment variable DEAL_II_NUM_THREADS, if set, is an upper
   * limit. Called once, after MPI is initialized. Also sets OpenBLAS (when it is the BLAS of the
   * process) to one thread unless OPENBLAS_NUM_THREADS or OMP_NUM_THREADS choose: BLAS threads
   * inside each subdomain's factorization would compete with these threads, and the bits of a
   * multithreaded factorization may depend on the number of threads.
   *
   * deal.II's own threads stay off (MPI_InitFinalize with one thread): its vector reductions
   * add in another order on several threads than on one, and the solvers' iterates would then
   * depend on the number of threads.
   */
  void
  initialize(const MPI_Comm comm);

  /** The number of threads that for_each() uses. */
  unsigned int
  n_threads();

  /**
   * Calls @p work(i) for i = 0, …, n − 1 on the threads of initialize() if @p threaded, in a
   * loop otherwise, and returns when all calls have returned; the first exception thrown by a
   * call is rethrown here. For the local work of FETI, one subdomain per call: assembly,
   * factorization, the solves with K_i⁺ inside every multiplication by F, the primal recovery.
   * Each call must write only memory of its own index (its subdomain's matrices and vectors, its
   * slots of B u); then the result is the same bits for any number of threads and any order in
   * which the threads take the indices.
   */
  void
  for_each(const unsigned int                             n,
           const std::function<void(const unsigned int)> &work,
           const bool                                     threaded = true);
} // namespace FetiContact::SubdomainThreads
