#pragma once

#include <deal.II/base/index_set.h>
#include <deal.II/base/partitioner.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <feticontact/base/exact_sum.h>

#include <cstdint>
#include <memory>
#include <mpi.h>
#include <vector>

namespace FetiContact
{
  /** A vector distributed over the ranks (deal.II's, with its Utilities::MPI::Partitioner). */
  using DistributedVector = dealii::LinearAlgebra::distributed::Vector<double>;

  /**
   * A deal.II partitioner whose owned entries carry a key and a chunk, for reductions over
   * DistributedVector that are the same bits on any number of ranks (reproducible_sum()).
   *
   * Every owned entry has a key (the caller's name for it, e.g. the number of a row of B, fixed
   * whatever the number of ranks) and a chunk: a set of entries that is held whole by one rank
   * on any number of ranks (for the FETI dual vectors, the rows whose first subdomain is the
   * same). The entries of a chunk are consecutive in the local storage, in increasing key. A
   * sum is made in two stages: a chunk falls into runs, largest sets of consecutive entries
   * whose keys follow each other; a run's terms are added in order with four partial sums by
   * position (a plain floating-point loop), and the runs' sums to their chunk's in order. The
   * chunks' sums are then added exactly and rounded once (ExactSum) over all ranks. The chunks
   * and runs are the same on any number of ranks, and so are the sums. A vector on a plain
   * deal.II partitioner has every entry its own chunk (every term added exactly: about six times
   * the cost of a plain sum; doc/performance.md, "Reproducible sums").
   *
   * Knows nothing of FETI.
   */
  class ReproduciblePartitioner : public dealii::Utilities::MPI::Partitioner
  {
  public:
    /**
     * The owned entries [@p first, @p first + key.size()) of @p n, the ghost entries
     * @p ghosts (global indices). @p key: the key of every owned entry; @p chunk: the chunk of
     * every owned entry (any numbers; the entries of one chunk consecutive, keys increasing), or
     * empty: every entry its own chunk. Collective (deal.II finds the ghosts' owners).
     */
    ReproduciblePartitioner(const MPI_Comm                        comm,
                            const dealii::types::global_dof_index first,
                            const dealii::types::global_dof_index n,
                            const dealii::IndexSet               &ghosts,
                            std::vector<unsigned int>             key,
                            const std::vector<unsigned int>      &chunk);

    /** The key of owned entry @p i (local index). */
    unsigned int
    key(const unsigned int i) const
    {
      return keys[i];
    }

    /** The keys of the owned entries. */
    const std::vector<unsigned int> &
    owned_keys() const
    {
      return keys;
    }

    /** Whether the entries fall into chunks (else every entry is its own). */
    bool
    chunked() const
    {
      return !run_start.empty();
    }

    /**
     * The runs: run r holds the owned entries [run_start[r], run_start[r + 1]); a run that
     * starts a new chunk has new_chunk[r] set.
     */
    std::vector<unsigned int> run_start;
    std::vector<bool>         new_chunk;
    /** The run of every owned entry. */
    std::vector<unsigned int> run_of_entry;

    /**
     * The global reductions made so far by the vectors of this partitioner (sums, minima,
     * maxima: one MPI_Allreduce each), the same number on every rank.
     */
    mutable std::uint64_t n_reductions = 0;

  private:
    std::vector<unsigned int> keys;
  };

  /**
   * Reductions over the ranks of numbers computed from the owned entries of a DistributedVector,
   * the same bits on any number of ranks. All collective.
   */
  namespace ReproducibleReductions
  {
    /** The ReproduciblePartitioner of @p v, or nullptr. */
    const ReproduciblePartitioner *
    partitioner_of(const DistributedVector &v);

    /** The exact sum of the terms of @p local over the ranks of @p v, rounded once. */
    double
    sum_over_ranks(ExactSum local, const DistributedVector &v);

    /** The minimum of @p local over the ranks of @p v. */
    double
    min(const double local, const DistributedVector &v);

    /** The maximum of @p local over the ranks of @p v. */
    double
    max(const double local, const DistributedVector &v);

    /** Whether @p local holds on some rank of @p v. */
    bool
    any(const bool local, const DistributedVector &v);

    /**
     * The sum over all owned entries i of all ranks of term(i), by the runs and chunks of the
     * vector's partitioner (see ReproduciblePartitioner).
     */
    template <typename Term>
    double
    sum(const DistributedVector &v, const Term &term)
    {
      ExactSum                       total;
      const ReproduciblePartitioner *p = partitioner_of(v);
      if (p == nullptr || !p->chunked())
        for (unsigned int i = 0; i < v.locally_owned_size(); ++i)
          total.add(term(i));
      else
        {
          // Each run with four partial sums by position, added pairwise; the runs' sums added
          // to their chunk's in order; the chunks' sums exactly.
          double chunk_sum = 0;
          for (unsigned int r = 0; r + 1 < p->run_start.size(); ++r)
            {
              if (p->new_chunk[r] && r > 0)
                {
                  total.add(chunk_sum);
                  chunk_sum = 0;
                }
              const unsigned int begin = p->run_start[r], n = p->run_start[r + 1] - begin;
              double             s[4] = {0, 0, 0, 0};
              unsigned int       j    = 0;
              for (; j + 4 <= n; j += 4)
                for (unsigned int q = 0; q < 4; ++q)
                  s[q] += term(begin + j + q);
              for (unsigned int q = 0; j < n; ++j, ++q)
                s[q] += term(begin + j);
              chunk_sum += (s[0] + s[1]) + (s[2] + s[3]);
            }
          if (p->run_start.size() > 1)
            total.add(chunk_sum);
        }
      return sum_over_ranks(total, v);
    }

    /** a · b. */
    double
    dot(const DistributedVector &a, const DistributedVector &b);

    /** ‖a‖². */
    double
    norm_sqr(const DistributedVector &a);

    /** ‖a‖ (scaled by ‖a‖_∞ where the squares would overflow or underflow). */
    double
    l2_norm(const DistributedVector &a);

    /** max |a_i|. */
    double
    linfty_norm(const DistributedVector &a);
  } // namespace ReproducibleReductions
} // namespace FetiContact
