#pragma once

#include <mpi.h>
#include <vector>

namespace FetiContact
{
  /**
   * A split of an index range [0, n) into contiguous blocks, one per MPI rank, for work on
   * replicated data that every rank could do alone: each rank computes the entries of its block,
   * and gather() gives every rank all of them. Every entry is computed by one rank with the same
   * operations in the same order as on one rank, so the result is the same bits on any number of
   * ranks; only the work is divided.
   *
   * Used for the products with G and Gᵀ (CoarseProblem), whose replicated passes over nnz(G)
   * numbers were a part of every Hessian multiplication that two ranks did twice, and for the
   * assignment of subdomains to ranks (Simulator).
   */
  class BlockPartition
  {
  public:
    /** The empty range (n = 0); assigned one of the others before use. */
    BlockPartition() = default;

    /**
     * Blocks balanced by a weight per index, given as its prefix sums (a CSR start array of
     * size n + 1: index i weighs weight_start[i + 1] − weight_start[i]).
     */
    static BlockPartition
    balanced(const MPI_Comm comm, const std::vector<unsigned int> &weight_start);

    /** The blocks with the given first indices (size n_ranks + 1, first 0, last n). */
    BlockPartition(const MPI_Comm comm, const std::vector<unsigned int> &first);

    /** The first index of this rank's block. */
    unsigned int
    begin() const
    {
      return first.empty() ? 0 : first[rank];
    }

    /** One past the last index of this rank's block. */
    unsigned int
    end() const
    {
      return first.empty() ? 0 : first[rank + 1];
    }

    /** The first index of every rank's block (size n_ranks + 1). */
    const std::vector<unsigned int> &
    firsts() const
    {
      return first;
    }

    /**
     * @p values (n numbers, this rank's block filled in) ← every rank's block: an
     * MPI_Allgatherv in place.
     */
    void
    gather(double *values) const;


  private:
    MPI_Comm                  comm = MPI_COMM_SELF;
    unsigned int              rank = 0;
    std::vector<unsigned int> first;
    std::vector<int>          count, displacement;
  };
} // namespace FetiContact
