#pragma once

#include <feticontact/base/exact_sum.h>

#include <cstdint>
#include <memory>
#include <mpi.h>
#include <vector>

namespace FetiContact
{
  /**
   * A vector of n numbers distributed over the MPI ranks of a communicator: each rank holds some
   * of its entries (every entry on exactly one rank) and knows their global indices. The
   * operations that the QP layer needs act on the local entries, and the reductions (dot
   * products and norms) are the same bits on any number of ranks and any split of the entries;
   * maxima and minima are exact anyway.
   *
   * A sum is made in two stages. The entries fall into chunks that the layout names, each held
   * whole by one rank whatever the number of ranks (for the FETI dual vectors: the rows whose
   * first subdomain is the same), and a chunk into runs of consecutive global indices. A run's
   * terms are added in the order of their global indices, with four partial sums by position
   * (a plain floating-point loop, contiguous in memory when the local entries are stored by
   * global index), and the runs' sums to their chunk's in the order of global indices: the
   * same numbers on any number of ranks. The chunks' sums are then added exactly and rounded
   * once (ExactSum) over all ranks. Without chunks every entry is its own chunk (about six times
   * the cost of a plain sum; doc/performance.md, "Reproducible sums").
   *
   * Local entries are addressed by their local index: operator[](i) is the i-th entry this rank
   * holds, whose global index is global_index(i) (an element-wise loop runs over i <
   * locally_owned_size()). size() is the global n, as for deal.II's distributed vectors.
   *
   * Written for the FETI dual vectors (each rank holds the rows of B that it adds up); knows
   * nothing of FETI. The QP layer is instantiated for it and for dealii::Vector<double>.
   */
  class DistributedVector
  {
  public:
    using value_type = double;
    using size_type  = unsigned int;

    /**
     * Which entries a rank holds: their global indices, in the order of the local entries, and
     * the global size. Shared by all vectors of one layout.
     */
    struct Layout
    {
      /**
       * @p global_index of the local entries; @p n_global the global size (all
       * ranks agree); @p chunk_of_entry: the chunk of every local entry (any numbers; entries
       * of one chunk must be local on one rank on any number of ranks), or empty: every entry
       * its own chunk.
       */
      Layout(const MPI_Comm               comm,
             std::vector<unsigned int>    global_index,
             const unsigned int           n,
             const std::vector<unsigned> &chunk_of_entry = {});

      MPI_Comm                  comm;
      std::vector<unsigned int> global_index;
      unsigned int              n_global;
      /** The local chunk number of every local entry (chunks numbered 0, 1, … locally). */
      std::vector<unsigned int> chunk;
      /** The number of local chunks (0: every entry its own chunk). */
      unsigned int n_local_chunks = 0;
      /**
       * The runs: largest sets of entries of one chunk with consecutive global indices, in the
       * order of global indices (CSR: the local entries run_entry[run_start[c]…], and the
       * chunk run_chunk[c] of run c).
       */
      std::vector<unsigned int> run_start, run_entry, run_chunk;
      /** The run of every local entry. */
      std::vector<unsigned int> run;
      /** Whether the local entries are stored by global index (run_entry the identity). */
      bool contiguous = false;
      /**
       * The global reductions made so far by the vectors of this layout (sums, minima, maxima,
       * any: one MPI_Allreduce each), the same number on every rank (doc/performance.md, the
       * parallel model).
       */
      mutable std::uint64_t n_reductions = 0;

      /** The number of local chunks (0: every entry its own chunk). */
      unsigned int
      n_chunks() const
      {
        return n_local_chunks;
      }
    };

    /** The empty vector (on no communicator). */
    DistributedVector() = default;

    /** A zero vector with @p layout. */
    explicit DistributedVector(std::shared_ptr<const Layout> layout);

    /** Makes this a vector with the layout of @p model, zero unless @p omit_zeroing. */
    void
    reinit(const DistributedVector &model, const bool omit_zeroing = false);

    /** Makes this a zero vector with @p layout. */
    void
    reinit(std::shared_ptr<const Layout> layout);

    /** The global size n (0 for the empty vector). */
    size_type
    size() const
    {
      return layout ? layout->n_global : 0;
    }

    /** The number of entries this rank holds. */
    size_type
    locally_owned_size() const
    {
      return values.size();
    }

    /** The global index of local entry @p i. */
    size_type
    global_index(const size_type i) const
    {
      return layout->global_index[i];
    }

    const std::shared_ptr<const Layout> &
    get_layout() const
    {
      return layout;
    }

    MPI_Comm
    get_mpi_communicator() const
    {
      return layout ? layout->comm : MPI_COMM_SELF;
    }

    /** Local entry @p i. */
    double &
    operator[](const size_type i)
    {
      return values[i];
    }

    double
    operator[](const size_type i) const
    {
      return values[i];
    }

    double *
    begin()
    {
      return values.data();
    }

    const double *
    begin() const
    {
      return values.data();
    }

    double *
    end()
    {
      return values.data() + values.size();
    }

    const double *
    end() const
    {
      return values.data() + values.size();
    }

    /** Every entry ← @p s. */
    DistributedVector &
    operator=(const double s);

    DistributedVector &
    operator+=(const DistributedVector &v);

    DistributedVector &
    operator-=(const DistributedVector &v);

    DistributedVector &
    operator*=(const double s);

    DistributedVector &
    operator/=(const double s);

    /** this ← this + a v. */
    void
    add(const double a, const DistributedVector &v);

    /** this ← this + a v + b w. */
    void
    add(const double a, const DistributedVector &v, const double b, const DistributedVector &w);

    /** this ← s this + a v. */
    void
    sadd(const double s, const double a, const DistributedVector &v);

    /** this ← a v. */
    void
    equ(const double a, const DistributedVector &v);

    /** this ← this ⊙ v, entry by entry. */
    void
    scale(const DistributedVector &v);

    void
    swap(DistributedVector &v);

    /** The dot product, exact and rounded once (the same on any number of ranks). */
    double
    operator*(const DistributedVector &v) const;

    /** ‖this‖², exact and rounded once. */
    double
    norm_sqr() const;

    /** ‖this‖ = √(norm_sqr()). */
    double
    l2_norm() const;

    /** max |entry|. */
    double
    linfty_norm() const;

    /** The exact sum of the terms of @p local over the ranks, rounded once. Collective. */
    double
    sum_over_ranks(ExactSum local) const;

    /** The minimum of @p local over the ranks. Collective. */
    double
    min_over_ranks(const double local) const;

    /** The maximum of @p local over the ranks. Collective. */
    double
    max_over_ranks(const double local) const;

    /** Whether @p local holds on some rank. Collective. */
    bool
    any_over_ranks(const bool local) const;

    /**
     * The sum over all entries of term(i) (i local), by runs and chunks (see the class): the
     * same bits on any number of ranks. Collective.
     */
    template <typename Term>
    double
    sum(const Term &term) const;

  private:
    /** @p local reduced over the ranks by @p operation (MPI_MIN, MPI_MAX). */
    double
    reduce(const double local, const MPI_Op operation) const;

    std::shared_ptr<const Layout> layout;
    std::vector<double>           values;
  };
  template <typename Term>
  inline double
  DistributedVector::sum(const Term &term) const
  {
    ExactSum total;
    if (!layout || layout->n_chunks() == 0)
      for (std::size_t i = 0; i < values.size(); ++i)
        total.add(term(i));
    else
      {
        // Each run with four partial sums by position, added pairwise; the runs' sums added to
        // their chunk's in the order of global indices; the chunks' sums exactly.
        std::vector<double> chunk_sum(layout->n_chunks(), 0.);
        for (unsigned int c = 0; c + 1 < layout->run_start.size(); ++c)
          {
            const unsigned int begin = layout->run_start[c], n = layout->run_start[c + 1] - begin;
            double             s[4] = {0, 0, 0, 0};
            unsigned int       j    = 0;
            if (layout->contiguous)
              {
                for (; j + 4 <= n; j += 4)
                  for (unsigned int q = 0; q < 4; ++q)
                    s[q] += term(begin + j + q);
                for (unsigned int q = 0; j < n; ++j, ++q)
                  s[q] += term(begin + j);
              }
            else
              {
                const unsigned int *entry = layout->run_entry.data() + begin;
                for (; j + 4 <= n; j += 4)
                  for (unsigned int q = 0; q < 4; ++q)
                    s[q] += term(entry[j + q]);
                for (unsigned int q = 0; j < n; ++j, ++q)
                  s[q] += term(entry[j]);
              }
            chunk_sum[layout->run_chunk[c]] += (s[0] + s[1]) + (s[2] + s[3]);
          }
        for (const double x : chunk_sum)
          total.add(x);
      }
    return sum_over_ranks(total);
  }

} // namespace FetiContact
