#pragma once

#include <feticontact/base/reproducible_partitioner.h>

namespace FetiContact::QP
{
  /**
   * What the QP layer needs of a vector type beyond its own element-wise operations: sums,
   * minima and maxima of numbers computed from the owned entries, taken over all ranks, dot
   * products and norms, and a key of an owned entry that does not depend on the number of
   * ranks. The QP layer is written for DistributedVector (deal.II's distributed vector): its
   * sums are ReproducibleReductions, the same bits on any number of ranks, and deal.II's own
   * dot products and norms (summed in rank order) are not used.
   */
  template <typename VectorType>
  struct Reductions;

  /** DistributedVector: reductions over the ranks, sums by the partitioner's runs and chunks. */
  template <>
  struct Reductions<DistributedVector>
  {
    using VectorType = DistributedVector;

    /**
     * A sum of the terms of all ranks by the runs and chunks of the vector's partitioner (see
     * ReproduciblePartitioner): the terms of a run in the order they are added, the runs' sums
     * to their chunk's in order, the chunks' sums exactly. Without chunks every term is added
     * exactly.
     */
    class Sum
    {
    public:
      explicit Sum(const VectorType &v)
        : partitioner(ReproducibleReductions::partitioner_of(v))
      {
        if (partitioner != nullptr && !partitioner->chunked())
          partitioner = nullptr;
        if (partitioner != nullptr)
          run_sum.assign(partitioner->run_start.size() - 1, 0.);
      }

      /** Adds the term @p x that belongs to owned entry @p i. */
      void
      add(const unsigned int i, const double x)
      {
        if (partitioner == nullptr)
          sum.add(x);
        else
          run_sum[partitioner->run_of_entry[i]] += x;
      }

      double
      result(const VectorType &v) const
      {
        ExactSum total(sum);
        if (partitioner != nullptr)
          {
            double chunk_sum = 0;
            for (unsigned int r = 0; r < run_sum.size(); ++r)
              {
                if (partitioner->new_chunk[r] && r > 0)
                  {
                    total.add(chunk_sum);
                    chunk_sum = 0;
                  }
                chunk_sum += run_sum[r];
              }
            if (!run_sum.empty())
              total.add(chunk_sum);
          }
        return ReproducibleReductions::sum_over_ranks(total, v);
      }

    private:
      const ReproduciblePartitioner *partitioner;
      std::vector<double>            run_sum;
      ExactSum                       sum;
    };

    /** The sum of term(i) over all owned entries i of all ranks. */
    template <typename Term>
    static double
    sum(const VectorType &v, const Term &term)
    {
      return ReproducibleReductions::sum(v, term);
    }

    static double
    min(const double local, const VectorType &v)
    {
      return ReproducibleReductions::min(local, v);
    }

    static double
    max(const double local, const VectorType &v)
    {
      return ReproducibleReductions::max(local, v);
    }

    static bool
    any(const bool local, const VectorType &v)
    {
      return ReproducibleReductions::any(local, v);
    }

    static double
    dot(const VectorType &a, const VectorType &b)
    {
      return ReproducibleReductions::dot(a, b);
    }

    static double
    norm_sqr(const VectorType &a)
    {
      return ReproducibleReductions::norm_sqr(a);
    }

    static double
    l2_norm(const VectorType &a)
    {
      return ReproducibleReductions::l2_norm(a);
    }

    static double
    linfty_norm(const VectorType &a)
    {
      return ReproducibleReductions::linfty_norm(a);
    }

    /**
     * The key of owned entry @p i: the partitioner's key, or the global index on a plain
     * partitioner (the same on any number of ranks).
     */
    static unsigned int
    global_index(const VectorType &v, const unsigned int i)
    {
      if (const ReproduciblePartitioner *p = ReproducibleReductions::partitioner_of(v))
        return p->key(i);
      return v.get_partitioner()->local_to_global(i);
    }
  };
} // namespace FetiContact::QP

namespace FetiContact::QP
{
  /** a · b over all ranks (Reductions). */
  template <typename VectorType>
  double
  dot(const VectorType &a, const VectorType &b)
  {
    return Reductions<VectorType>::dot(a, b);
  }

  /** ‖a‖² over all ranks (Reductions). */
  template <typename VectorType>
  double
  norm_sqr(const VectorType &a)
  {
    return Reductions<VectorType>::norm_sqr(a);
  }

  /** ‖a‖ over all ranks (Reductions). */
  template <typename VectorType>
  double
  l2_norm(const VectorType &a)
  {
    return Reductions<VectorType>::l2_norm(a);
  }

  /** max |a_i| over all ranks (Reductions). */
  template <typename VectorType>
  double
  linfty_norm(const VectorType &a)
  {
    return Reductions<VectorType>::linfty_norm(a);
  }
} // namespace FetiContact::QP
