#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/base/exact_sum.h>
#include <feticontact/feti/dual_problem.h>

#include <memory>
#include <vector>

namespace FetiContact
{
  /**
   * The rows of the dual problem that this rank holds in its dual vectors: the rows it adds up
   * in F x (DualProblem::space()), and the conversions to and from vectors of all rows.
   *
   * For the solvers that act on rows by their meaning (the contact rows of a node, the blocks
   * λ_T and λ_c of the Gauss–Seidel split): they loop over the local entries and reduce counts,
   * maxima and exact sums over the ranks here. Knows nothing of contact.
   */
  class LocalDualRows
  {
  public:
    explicit LocalDualRows(const DualProblem &dual);

    /** A zero dual vector. */
    DualVector
    vector() const;

    /** h of the dual problem on this rank's rows. */
    const DualVector &
    h() const;

    /** c (the right-hand side of B u = c, B u ≤ c) on this rank's rows. */
    const DualVector &
    c() const;

    /** The entries this rank holds of a vector of all rows. */
    DualVector restrict(const dealii::Vector<double> &all) const;

    /** All rows of @p x on every rank (collective). */
    dealii::Vector<double>
    gather(const DualVector &x) const;

    /**
     * The local index of row @p row, or numbers::invalid_unsigned_int if this rank does not own
     * it.
     */
    unsigned int
    local_index(const unsigned int row) const;

    /** The number of the row of owned entry @p i. */
    unsigned int
    row(const unsigned int i) const
    {
      return space.row(i);
    }

    /** The number of entries this rank holds. */
    unsigned int
    n_local() const;

    /**
     * The rows [first, first + n) as a dual vector of their own (the blocks of a Gauss–Seidel
     * split): the owned entries of a vector of all rows in the block (in their order), and the
     * partitioner of the block's vectors (their sums are taken in the same chunks; the key of a
     * row is its number less @p first).
     */
    struct Block
    {
      unsigned int                                   first = 0, n = 0;
      std::vector<unsigned int>                      entries;
      std::shared_ptr<const ReproduciblePartitioner> partitioner;

      /** The index in the block's vectors of owned entry @p i of a vector of all rows. */
      unsigned int
      index_of(const unsigned int i) const;
      /** A zero vector of the block. */
      DualVector
      vector() const;
      /** @p part ← the block's entries of @p full. */
      void
      extract(const DualVector &full, DualVector &part) const;
      /** The block's entries of @p full ← @p part. */
      void
      insert(const DualVector &part, DualVector &full) const;
    };

    /** The block of rows [first, first + n). */
    Block
    block(const unsigned int first, const unsigned int n) const;

    /** Every entry of @p counts summed over the ranks. */
    void
    sum_over_ranks(std::vector<unsigned int> &counts) const;

    /** The maximum of @p local over the ranks. */
    double
    max_over_ranks(const double local) const;

    /**
     * Every sum of @p sums made the exact sum of its terms on all ranks: the same bits on any
     * number of ranks (one reduction).
     */
    void
    sum_over_ranks(std::vector<ExactSum> &sums) const;

  private:
    const DualProblem &dual;
    const DualSpace   &space;
  };
} // namespace FetiContact
