#pragma once

#include <deal.II/base/mpi.h>

#include <mpi.h>
#include <string>
#include <type_traits>
#include <vector>

namespace FetiContact::MPITools
{
  /**
   * The message of the lowest rank whose @p local_error (its message; empty if it succeeded) is
   * not empty, on every rank; empty if no rank failed. Collective: so that all ranks stop
   * together with the same message.
   */
  inline std::string
  first_error(const MPI_Comm comm, const std::string &local_error)
  {
    const unsigned int rank         = dealii::Utilities::MPI::this_mpi_process(comm);
    const unsigned int first_failed = dealii::Utilities::MPI::min(
      local_error.empty() ? dealii::numbers::invalid_unsigned_int : rank, comm);
    if (first_failed == dealii::numbers::invalid_unsigned_int)
      return {};
    return dealii::Utilities::MPI::broadcast(comm, local_error, first_failed);
  }

  /**
   * Runs @p work on this rank and makes an @p Error (an exception type constructible from its
   * message) thrown on any rank of @p comm every rank's: every rank then throws @p Error with the
   * message of the lowest failing rank (first_error()), so that all ranks stop together. Other
   * exceptions pass through on the rank that throws them. Collective.
   */
  template <typename Error, typename Work>
  void
  collectively(const MPI_Comm comm, const Work &work)
  {
    std::string error;
    try
      {
        work();
      }
    catch (const Error &e)
      {
        error = e.what();
        if (error.empty())
          error = "failed";
      }
    error = first_error(comm, error);
    if (!error.empty())
      throw Error(error);
  }

  /**
   * The concatenation, in rank order, of every rank's @p local (trivially copyable T), sent as
   * raw bytes. deal.II's Utilities::MPI::all_gather serializes each rank's object through boost
   * and returns a vector per rank; this one is used for the entries of G (the coarse problem)
   * and the shared local work, 10⁵–10⁶ entries at 10⁶ unknowns. Sums use Utilities::MPI::sum.
   */
  template <typename T>
  std::vector<T>
  all_gather(const MPI_Comm comm, const std::vector<T> &local)
  {
    static_assert(std::is_trivially_copyable_v<T>);
    int n_ranks = 1;
    MPI_Comm_size(comm, &n_ranks);
    const int        bytes = local.size() * sizeof(T);
    std::vector<int> counts(n_ranks), offsets(n_ranks + 1, 0);
    MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
    for (int r = 0; r < n_ranks; ++r)
      offsets[r + 1] = offsets[r] + counts[r];
    std::vector<T> all(offsets[n_ranks] / sizeof(T));
    MPI_Allgatherv(
      local.data(), bytes, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, comm);
    return all;
  }

  /**
   * The concatenation, in rank order, of every rank's @p local on rank @p root of @p comm (empty
   * on the other ranks): all_gather() to one rank.
   */
  template <typename T>
  std::vector<T>
  gather(const MPI_Comm comm, const std::vector<T> &local, const int root)
  {
    static_assert(std::is_trivially_copyable_v<T>);
    int n_ranks = 1, rank = 0;
    MPI_Comm_size(comm, &n_ranks);
    MPI_Comm_rank(comm, &rank);
    const int        bytes = local.size() * sizeof(T);
    std::vector<int> counts(n_ranks), offsets(n_ranks + 1, 0);
    MPI_Gather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, root, comm);
    for (int r = 0; r < n_ranks; ++r)
      offsets[r + 1] = offsets[r] + counts[r];
    std::vector<T> all(rank == root ? offsets[n_ranks] / sizeof(T) : 0);
    MPI_Gatherv(local.data(),
                bytes,
                MPI_BYTE,
                all.data(),
                counts.data(),
                offsets.data(),
                MPI_BYTE,
                root,
                comm);
    return all;
  }
} // namespace FetiContact::MPITools
