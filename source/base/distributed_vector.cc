#include <deal.II/base/exceptions.h>

#include <feticontact/base/distributed_vector.h>

#include <algorithm>
#include <cmath>

namespace FetiContact
{
  DistributedVector::Layout::Layout(const MPI_Comm            comm,
                                    std::vector<unsigned int> global_index,
                                    const unsigned int        n)
    : comm(comm)
    , global_index(std::move(global_index))
    , n_global(n)
  {}

  DistributedVector::DistributedVector(std::shared_ptr<const Layout> layout)
  {
    reinit(std::move(layout));
  }

  void
  DistributedVector::reinit(const DistributedVector &model, const bool omit_zeroing)
  {
    layout = model.layout;
    if (omit_zeroing)
      values.resize(model.values.size());
    else
      values.assign(model.values.size(), 0.);
  }

  void
  DistributedVector::reinit(std::shared_ptr<const Layout> new_layout)
  {
    layout = std::move(new_layout);
    values.assign(layout ? layout->global_index.size() : 0, 0.);
  }

  DistributedVector &
  DistributedVector::operator=(const double s)
  {
    std::fill(values.begin(), values.end(), s);
    return *this;
  }

  DistributedVector &
  DistributedVector::operator+=(const DistributedVector &v)
  {
    AssertDimension(v.values.size(), values.size());
    for (std::size_t i = 0; i < values.size(); ++i)
      values[i] += v.values[i];
    return *this;
  }

  DistributedVector &
  DistributedVector::operator-=(const DistributedVector &v)
  {
    AssertDimension(v.values.size(), values.size());
    for (std::size_t i = 0; i < values.size(); ++i)
      values[i] -= v.values[i];
    return *this;
  }

  DistributedVector &
  DistributedVector::operator*=(const double s)
  {
    for (double &x : values)
      x *= s;
    return *this;
  }

  DistributedVector &
  DistributedVector::operator/=(const double s)
  {
    for (double &x : values)
      x /= s;
    return *this;
  }

  void
  DistributedVector::add(const double a, const DistributedVector &v)
  {
    AssertDimension(v.values.size(), values.size());
    for (std::size_t i = 0; i < values.size(); ++i)
      values[i] += a * v.values[i];
  }

  void
  DistributedVector::add(const double             a,
                         const DistributedVector &v,
                         const double             b,
                         const DistributedVector &w)
  {
    AssertDimension(v.values.size(), values.size());
    AssertDimension(w.values.size(), values.size());
    for (std::size_t i = 0; i < values.size(); ++i)
      values[i] += a * v.values[i] + b * w.values[i];
  }

  void
  DistributedVector::sadd(const double s, const double a, const DistributedVector &v)
  {
    AssertDimension(v.values.size(), values.size());
    for (std::size_t i = 0; i < values.size(); ++i)
      values[i] = s * values[i] + a * v.values[i];
  }

  void
  DistributedVector::equ(const double a, const DistributedVector &v)
  {
    layout = v.layout;
    values.resize(v.values.size());
    for (std::size_t i = 0; i < values.size(); ++i)
      values[i] = a * v.values[i];
  }

  void
  DistributedVector::scale(const DistributedVector &v)
  {
    AssertDimension(v.values.size(), values.size());
    for (std::size_t i = 0; i < values.size(); ++i)
      values[i] *= v.values[i];
  }

  void
  DistributedVector::swap(DistributedVector &v)
  {
    std::swap(layout, v.layout);
    values.swap(v.values);
  }

  double
  DistributedVector::operator*(const DistributedVector &v) const
  {
    AssertDimension(v.values.size(), values.size());
    ExactSum sum;
    for (std::size_t i = 0; i < values.size(); ++i)
      sum.add_product(values[i], v.values[i]);
    return sum_over_ranks(sum);
  }

  double
  DistributedVector::norm_sqr() const
  {
    ExactSum sum;
    for (const double x : values)
      sum.add_product(x, x);
    return sum_over_ranks(sum);
  }

  double
  DistributedVector::l2_norm() const
  {
    return std::sqrt(norm_sqr());
  }

  double
  DistributedVector::linfty_norm() const
  {
    double norm = 0;
    for (const double x : values)
      norm = std::max(norm, std::abs(x));
    return max_over_ranks(norm);
  }

  double
  DistributedVector::sum_over_ranks(ExactSum local) const
  {
    if (layout)
      local.sum_over_ranks(layout->comm);
    return local.value();
  }

  double
  DistributedVector::reduce(const double local, const MPI_Op operation) const
  {
    double global = local;
    if (layout)
      MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, operation, layout->comm);
    return global;
  }

  double
  DistributedVector::min_over_ranks(const double local) const
  {
    return reduce(local, MPI_MIN);
  }

  double
  DistributedVector::max_over_ranks(const double local) const
  {
    return reduce(local, MPI_MAX);
  }

  bool
  DistributedVector::any_over_ranks(const bool local) const
  {
    int global = local ? 1 : 0;
    if (layout)
      MPI_Allreduce(MPI_IN_PLACE, &global, 1, MPI_INT, MPI_MAX, layout->comm);
    return global != 0;
  }
} // namespace FetiContact
