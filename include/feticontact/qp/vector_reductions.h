#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/base/distributed_vector.h>

namespace FetiContact::QP
{
  /**
   * What the QP layer needs of a vector type beyond its own operations: sums, minima and maxima
   * of numbers computed from the local entries, taken over all entries (over the ranks for a
   * distributed vector), and the global index of a local entry. The QP layer is instantiated for
   * dealii::Vector<double> (one process holds everything; sums in the order of the entries) and
   * DistributedVector (sums exact and rounded once, so the same bits on any number of ranks).
   */
  template <typename VectorType>
  struct Reductions;

  /** dealii::Vector<double>: every entry is local, sums in the order of the terms. */
  template <>
  struct Reductions<dealii::Vector<double>>
  {
    using VectorType = dealii::Vector<double>;

    /** A sum of terms, in the order they are added. */
    class Sum
    {
    public:
      explicit Sum(const VectorType &)
      {}

      /** Adds the term @p x that belongs to entry @p i. */
      void
      add(const unsigned int /*i*/, const double x)
      {
        sum += x;
      }

      double
      result(const VectorType &) const
      {
        return sum;
      }

    private:
      double sum = 0;
    };

    /** The sum of term(i) over all entries, in the order of the entries. */
    template <typename Term>
    static double
    sum(const VectorType &v, const Term &term)
    {
      double sum = 0;
      for (unsigned int i = 0; i < v.size(); ++i)
        sum += term(i);
      return sum;
    }

    static double
    min(const double local, const VectorType &)
    {
      return local;
    }

    static double
    max(const double local, const VectorType &)
    {
      return local;
    }

    static bool
    any(const bool local, const VectorType &)
    {
      return local;
    }

    static unsigned int
    global_index(const VectorType &, const unsigned int i)
    {
      return i;
    }
  };

  /** DistributedVector: reductions over the ranks, sums exact. */
  template <>
  struct Reductions<DistributedVector>
  {
    using VectorType = DistributedVector;

    /**
     * A sum of the terms of all ranks by the runs and chunks of the vector's layout (see
     * DistributedVector): the terms of a run in the order they are added, the runs' sums to
     * their chunk's in the order of global indices, the chunks' sums exactly. Without chunks,
     * or if the local entries are not stored by global index (then the order in which the
     * caller adds a run's terms could depend on the split), every term is added exactly.
     */
    class Sum
    {
    public:
      explicit Sum(const VectorType &v)
        : layout(v.get_layout() && v.get_layout()->n_chunks() > 0 && v.get_layout()->contiguous ?
                   v.get_layout().get() :
                   nullptr)
        , run_sum(layout ? layout->run_chunk.size() : 0, 0.)
      {}

      /** Adds the term @p x that belongs to local entry @p i. */
      void
      add(const unsigned int i, const double x)
      {
        if (layout == nullptr)
          sum.add(x);
        else
          run_sum[layout->run[i]] += x;
      }

      double
      result(const VectorType &v) const
      {
        ExactSum total(sum);
        if (layout != nullptr)
          {
            std::vector<double> chunk_sum(layout->n_chunks(), 0.);
            for (unsigned int r = 0; r < run_sum.size(); ++r)
              chunk_sum[layout->run_chunk[r]] += run_sum[r];
            for (const double s : chunk_sum)
              total.add(s);
          }
        return v.sum_over_ranks(total);
      }

    private:
      const DistributedVector::Layout *layout;
      std::vector<double>              run_sum;
      ExactSum                         sum;
    };

    /** The sum of term(i) over all local entries i of all ranks (DistributedVector::sum). */
    template <typename Term>
    static double
    sum(const VectorType &v, const Term &term)
    {
      return v.sum(term);
    }

    static double
    min(const double local, const VectorType &v)
    {
      return v.min_over_ranks(local);
    }

    static double
    max(const double local, const VectorType &v)
    {
      return v.max_over_ranks(local);
    }

    static bool
    any(const bool local, const VectorType &v)
    {
      return v.any_over_ranks(local);
    }

    static unsigned int
    global_index(const VectorType &v, const unsigned int i)
    {
      return v.global_index(i);
    }
  };
} // namespace FetiContact::QP
