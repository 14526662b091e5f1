#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <feticontact/feti/local_dual_rows.h>

#include <algorithm>

namespace FetiContact
{
  using namespace dealii;

  LocalDualRows::LocalDualRows(const DualProblem &dual)
    : dual(dual)
    , layout(dual.distribution().layout())
  {}

  DualVector
  LocalDualRows::vector() const
  {
    return dual.distribution().vector();
  }

  const DualVector &
  LocalDualRows::h() const
  {
    return dual.h;
  }

  const DualVector &
  LocalDualRows::c() const
  {
    return dual.c;
  }

  DualVector LocalDualRows::restrict(const Vector<double> &all) const
  {
    return dual.distribution().restrict(all);
  }

  Vector<double>
  LocalDualRows::gather(const DualVector &x) const
  {
    return dual.distribution().gather(x);
  }

  unsigned int
  LocalDualRows::local_index(const unsigned int row) const
  {
    const auto &rows = layout->global_index;
    const auto  it   = std::lower_bound(rows.begin(), rows.end(), row);
    return it != rows.end() && *it == row ? it - rows.begin() : numbers::invalid_unsigned_int;
  }

  unsigned int
  LocalDualRows::n_local() const
  {
    return layout->global_index.size();
  }

  LocalDualRows::Block
  LocalDualRows::block(const unsigned int first, const unsigned int n) const
  {
    Block b;
    b.first          = first;
    b.n              = n;
    const auto &rows = layout->global_index;
    Assert(std::is_sorted(rows.begin(), rows.end()), ExcInternalError());
    b.begin = std::lower_bound(rows.begin(), rows.end(), first) - rows.begin();
    b.end   = std::lower_bound(rows.begin(), rows.end(), first + n) - rows.begin();
    std::vector<unsigned int> index(b.end - b.begin), chunk;
    for (unsigned int i = b.begin; i < b.end; ++i)
      index[i - b.begin] = rows[i] - first;
    if (layout->n_chunks() > 0)
      chunk.assign(layout->chunk.begin() + b.begin, layout->chunk.begin() + b.end);
    b.layout =
      std::make_shared<const DistributedVector::Layout>(layout->comm, std::move(index), n, chunk);
    return b;
  }

  DualVector
  LocalDualRows::Block::vector() const
  {
    return DistributedVector(layout);
  }

  void
  LocalDualRows::Block::extract(const DualVector &full, DualVector &part) const
  {
    if (part.size() != n)
      part = vector();
    for (unsigned int i = begin; i < end; ++i)
      part[i - begin] = full[i];
  }

  void
  LocalDualRows::Block::insert(const DualVector &part, DualVector &full) const
  {
    for (unsigned int i = begin; i < end; ++i)
      full[i] = part[i - begin];
  }

  void
  LocalDualRows::sum_over_ranks(std::vector<unsigned int> &counts) const
  {
    Utilities::MPI::sum(ArrayView<const unsigned int>(counts.data(), counts.size()),
                        layout->comm,
                        ArrayView<unsigned int>(counts.data(), counts.size()));
    ++layout->n_reductions;
  }

  double
  LocalDualRows::max_over_ranks(const double local) const
  {
    ++layout->n_reductions;
    return Utilities::MPI::max(local, layout->comm);
  }

  void
  LocalDualRows::sum_over_ranks(std::vector<ExactSum> &sums) const
  {
    ++layout->n_reductions;
    ExactSum::sum_over_ranks(sums, layout->comm);
  }

} // namespace FetiContact
