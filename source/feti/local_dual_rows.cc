#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <feticontact/feti/local_dual_rows.h>

#include <algorithm>

namespace FetiContact
{
  using namespace dealii;

  template <typename VectorType>
  LocalDualRows<VectorType>::LocalDualRows(const DualProblem &dual)
    : dual(dual)
  {
    if constexpr (distributed)
      layout = dual.distribution().layout();
  }

  template <typename VectorType>
  VectorType
  LocalDualRows<VectorType>::vector() const
  {
    if constexpr (distributed)
      return dual.distribution().vector();
    else
      return Vector<double>(dual.size());
  }

  template <typename VectorType>
  const VectorType &
  LocalDualRows<VectorType>::h() const
  {
    if constexpr (distributed)
      return dual.h_owned;
    else
      return dual.h;
  }

  template <typename VectorType>
  const VectorType &
  LocalDualRows<VectorType>::c() const
  {
    if constexpr (distributed)
      return dual.c_owned;
    else
      return dual.c;
  }

  template <typename VectorType>
  VectorType LocalDualRows<VectorType>::restrict(const Vector<double> &all) const
  {
    if constexpr (distributed)
      return dual.distribution().restrict(all);
    else
      return all;
  }

  template <typename VectorType>
  Vector<double>
  LocalDualRows<VectorType>::gather(const VectorType &x) const
  {
    if constexpr (distributed)
      return dual.distribution().gather(x);
    else
      return x;
  }

  template <typename VectorType>
  unsigned int
  LocalDualRows<VectorType>::local_index(const unsigned int row) const
  {
    if constexpr (distributed)
      {
        const auto &rows = layout->global_index;
        const auto  it   = std::lower_bound(rows.begin(), rows.end(), row);
        return it != rows.end() && *it == row ? it - rows.begin() : numbers::invalid_unsigned_int;
      }
    else
      return row;
  }

  template <typename VectorType>
  unsigned int
  LocalDualRows<VectorType>::n_local() const
  {
    if constexpr (distributed)
      return layout->global_index.size();
    else
      return dual.size();
  }

  template <typename VectorType>
  typename LocalDualRows<VectorType>::Block
  LocalDualRows<VectorType>::block(const unsigned int first, const unsigned int n) const
  {
    Block b;
    b.first = first;
    b.n     = n;
    if constexpr (distributed)
      {
        const auto &rows = layout->global_index;
        Assert(std::is_sorted(rows.begin(), rows.end()), ExcInternalError());
        b.begin = std::lower_bound(rows.begin(), rows.end(), first) - rows.begin();
        b.end   = std::lower_bound(rows.begin(), rows.end(), first + n) - rows.begin();
        std::vector<unsigned int> index(b.end - b.begin), chunk;
        for (unsigned int i = b.begin; i < b.end; ++i)
          index[i - b.begin] = rows[i] - first;
        if (layout->n_chunks() > 0)
          chunk.assign(layout->chunk.begin() + b.begin, layout->chunk.begin() + b.end);
        b.layout = std::make_shared<const DistributedVector::Layout>(layout->comm,
                                                                     std::move(index),
                                                                     n,
                                                                     chunk);
      }
    else
      {
        b.begin = first;
        b.end   = first + n;
      }
    return b;
  }

  template <typename VectorType>
  VectorType
  LocalDualRows<VectorType>::Block::vector() const
  {
    if constexpr (distributed)
      return DistributedVector(layout);
    else
      return Vector<double>(n);
  }

  template <typename VectorType>
  void
  LocalDualRows<VectorType>::Block::extract(const VectorType &full, VectorType &part) const
  {
    if (part.size() != n)
      part = vector();
    for (unsigned int i = begin; i < end; ++i)
      part[i - begin] = full[i];
  }

  template <typename VectorType>
  void
  LocalDualRows<VectorType>::Block::insert(const VectorType &part, VectorType &full) const
  {
    for (unsigned int i = begin; i < end; ++i)
      full[i] = part[i - begin];
  }

  template <typename VectorType>
  void
  LocalDualRows<VectorType>::sum_over_ranks(std::vector<unsigned int> &counts) const
  {
    if constexpr (distributed)
      {
        Utilities::MPI::sum(ArrayView<const unsigned int>(counts.data(), counts.size()),
                            layout->comm,
                            ArrayView<unsigned int>(counts.data(), counts.size()));
        ++layout->n_reductions;
      }
  }

  template <typename VectorType>
  double
  LocalDualRows<VectorType>::max_over_ranks(const double local) const
  {
    if constexpr (distributed)
      {
        ++layout->n_reductions;
        return Utilities::MPI::max(local, layout->comm);
      }
    return local;
  }

  template <typename VectorType>
  void
  LocalDualRows<VectorType>::sum_over_ranks(std::vector<ExactSum> &sums) const
  {
    if constexpr (distributed)
      {
        ++layout->n_reductions;
        ExactSum::sum_over_ranks(sums, layout->comm);
      }
  }

  template class LocalDualRows<Vector<double>>;
  template class LocalDualRows<DistributedVector>;
} // namespace FetiContact
