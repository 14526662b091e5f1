#include <deal.II/base/exceptions.h>

#include <feticontact/base/reproducible_partitioner.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    IndexSet
    owned_range(const types::global_dof_index first,
                const std::size_t             n_owned,
                const types::global_dof_index n)
    {
      IndexSet owned(n);
      owned.add_range(first, first + n_owned);
      return owned;
    }
  } // namespace

  ReproduciblePartitioner::ReproduciblePartitioner(const MPI_Comm                   comm,
                                                   const types::global_dof_index    first,
                                                   const types::global_dof_index    n,
                                                   const IndexSet                  &ghosts,
                                                   std::vector<unsigned int>        key,
                                                   const std::vector<unsigned int> &chunk)
    : Utilities::MPI::Partitioner(owned_range(first, key.size(), n), comm)
    , keys(std::move(key))
  {
    // The ghosts' owners (deal.II's consensus algorithm), unless no rank has ghosts: it fails
    // on an empty vector, and a block without ghosts needs no exchange.
    if (n > 0 && Utilities::MPI::max(ghosts.n_elements(), comm) > 0)
      set_ghost_indices(ghosts);
    if (chunk.empty())
      return;
    AssertDimension(chunk.size(), keys.size());
    // Runs: largest sets of consecutive entries of one chunk whose keys follow each other.
    const unsigned int n_owned = keys.size();
    run_of_entry.resize(n_owned);
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        const bool chunk_starts = i == 0 || chunk[i] != chunk[i - 1];
        AssertThrow(chunk_starts || keys[i] > keys[i - 1],
                    ExcMessage("ReproduciblePartitioner: the keys of a chunk must increase."));
        if (chunk_starts || keys[i] != keys[i - 1] + 1)
          {
            run_start.push_back(i);
            new_chunk.push_back(chunk_starts);
          }
        run_of_entry[i] = run_start.size() - 1;
      }
    run_start.push_back(n_owned);
  }

  namespace ReproducibleReductions
  {
    const ReproduciblePartitioner *
    partitioner_of(const DistributedVector &v)
    {
      return dynamic_cast<const ReproduciblePartitioner *>(v.get_partitioner().get());
    }

    namespace
    {
      void
      count_reduction(const DistributedVector &v)
      {
        if (const ReproduciblePartitioner *p = partitioner_of(v))
          ++p->n_reductions;
      }

      double
      reduce(const double local, const MPI_Op operation, const DistributedVector &v)
      {
        double global = local;
        MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, operation, v.get_mpi_communicator());
        count_reduction(v);
        return global;
      }
    } // namespace

    double
    sum_over_ranks(ExactSum local, const DistributedVector &v)
    {
      local.sum_over_ranks(v.get_mpi_communicator());
      count_reduction(v);
      return local.value();
    }

    double
    min(const double local, const DistributedVector &v)
    {
      return reduce(local, MPI_MIN, v);
    }

    double
    max(const double local, const DistributedVector &v)
    {
      return reduce(local, MPI_MAX, v);
    }

    bool
    any(const bool local, const DistributedVector &v)
    {
      int global = local ? 1 : 0;
      MPI_Allreduce(MPI_IN_PLACE, &global, 1, MPI_INT, MPI_MAX, v.get_mpi_communicator());
      count_reduction(v);
      return global != 0;
    }

    double
    dot(const DistributedVector &a, const DistributedVector &b)
    {
      AssertDimension(a.locally_owned_size(), b.locally_owned_size());
      const double *x = a.begin(), *y = b.begin();
      return sum(a, [x, y](const unsigned int i) { return x[i] * y[i]; });
    }

    double
    norm_sqr(const DistributedVector &a)
    {
      const double *x = a.begin();
      return sum(a, [x](const unsigned int i) { return x[i] * x[i]; });
    }

    double
    l2_norm(const DistributedVector &a)
    {
      const double sum_of_squares = norm_sqr(a);
      if (std::isnan(sum_of_squares) ||
          (std::isfinite(sum_of_squares) && sum_of_squares >= std::numeric_limits<double>::min()))
        return std::sqrt(sum_of_squares);
      // The squares overflowed or underflowed: the norm of x/‖x‖_∞, times ‖x‖_∞ (as
      // dealii::Vector::l2_norm does).
      const double scale = linfty_norm(a);
      if (scale == 0 || !std::isfinite(scale))
        return scale;
      const double *x = a.begin();
      return scale * std::sqrt(sum(a, [x, scale](const unsigned int i) {
               return (x[i] / scale) * (x[i] / scale);
             }));
    }

    double
    linfty_norm(const DistributedVector &a)
    {
      double norm = 0;
      for (unsigned int i = 0; i < a.locally_owned_size(); ++i)
        norm = std::max(norm, std::abs(a.local_element(i)));
      return max(norm, a);
    }
  } // namespace ReproducibleReductions
} // namespace FetiContact
