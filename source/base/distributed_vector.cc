#include <deal.II/base/exceptions.h>

#include <feticontact/base/distributed_vector.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace FetiContact
{
  DistributedVector::Layout::Layout(const MPI_Comm               comm,
                                    std::vector<unsigned int>    global_index,
                                    const unsigned int           n,
                                    const std::vector<unsigned> &chunk_of_entry)
    : comm(comm)
    , global_index(std::move(global_index))
    , n_global(n)
  {
    if (chunk_of_entry.empty())
      return;
    AssertDimension(chunk_of_entry.size(), this->global_index.size());
    // Local chunk numbers in the order of the given ones.
    std::vector<unsigned int> keys(chunk_of_entry);
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    n_local_chunks             = keys.size();
    const unsigned int n_local = this->global_index.size();
    chunk.resize(n_local);
    for (unsigned int i = 0; i < n_local; ++i)
      chunk[i] = std::lower_bound(keys.begin(), keys.end(), chunk_of_entry[i]) - keys.begin();
    // The local entries by global index, cut into runs of consecutive global indices of one
    // chunk: the same runs on any number of ranks, since a chunk is whole on one rank.
    run_entry.resize(n_local);
    run.resize(n_local);
    std::iota(run_entry.begin(), run_entry.end(), 0u);
    if (!std::is_sorted(this->global_index.begin(), this->global_index.end()))
      std::sort(run_entry.begin(), run_entry.end(), [this](const unsigned a, const unsigned b) {
        return this->global_index[a] < this->global_index[b];
      });
    for (unsigned int j = 0; j < n_local; ++j)
      {
        const unsigned int i = run_entry[j];
        if (j == 0 || chunk[i] != chunk[run_entry[j - 1]] ||
            this->global_index[i] != this->global_index[run_entry[j - 1]] + 1)
          {
            run_start.push_back(j);
            run_chunk.push_back(chunk[i]);
          }
        run[i] = run_start.size() - 1;
      }
    run_start.push_back(n_local);
    contiguous = true;
    for (unsigned int j = 0; j < n_local; ++j)
      contiguous = contiguous && run_entry[j] == j;
  }

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
    const double *a = values.data(), *b = v.values.data();
    return sum([a, b](const unsigned int i) { return a[i] * b[i]; });
  }

  double
  DistributedVector::norm_sqr() const
  {
    const double *a = values.data();
    return sum([a](const unsigned int i) { return a[i] * a[i]; });
  }

  double
  DistributedVector::l2_norm() const
  {
    const double sum_of_squares = norm_sqr();
    if (std::isnan(sum_of_squares) ||
        (std::isfinite(sum_of_squares) && sum_of_squares >= std::numeric_limits<double>::min()))
      return std::sqrt(sum_of_squares);
    // The squares overflowed or underflowed: the norm of x/‖x‖_∞, times ‖x‖_∞ (as
    // dealii::Vector::l2_norm does).
    const double scale = linfty_norm();
    if (scale == 0 || !std::isfinite(scale))
      return scale;
    const double *a = values.data();
    return scale * std::sqrt(sum(
                     [a, scale](const unsigned int i) { return (a[i] / scale) * (a[i] / scale); }));
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
      {
        local.sum_over_ranks(layout->comm);
        ++layout->n_reductions;
      }
    return local.value();
  }

  double
  DistributedVector::reduce(const double local, const MPI_Op operation) const
  {
    double global = local;
    if (layout)
      {
        MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, operation, layout->comm);
        ++layout->n_reductions;
      }
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
      {
        MPI_Allreduce(MPI_IN_PLACE, &global, 1, MPI_INT, MPI_MAX, layout->comm);
        ++layout->n_reductions;
      }
    return global != 0;
  }
} // namespace FetiContact
