#include <deal.II/base/exceptions.h>

#include <feticontact/base/block_partition.h>

#include <algorithm>

namespace FetiContact
{
  BlockPartition
  BlockPartition::balanced(const MPI_Comm comm, const std::vector<unsigned int> &weight_start)
  {
    int n_ranks = 1;
    MPI_Comm_size(comm, &n_ranks);
    AssertThrow(!weight_start.empty(), dealii::ExcMessage("BlockPartition: no prefix sums."));
    const unsigned int        n     = weight_start.size() - 1;
    const double              total = weight_start.back() - weight_start.front();
    std::vector<unsigned int> first(n_ranks + 1, n);
    first[0] = 0;
    // Block p begins at the first index whose preceding weight reaches p/n_ranks of the total.
    for (int p = 1; p < n_ranks; ++p)
      {
        const double target = weight_start.front() + total * p / n_ranks;
        first[p] = std::lower_bound(weight_start.begin(), weight_start.end() - 1, target) -
                   weight_start.begin();
        first[p] = std::max(first[p], first[p - 1]);
      }
    return BlockPartition(comm, first);
  }

  BlockPartition::BlockPartition(const MPI_Comm comm, const std::vector<unsigned int> &first)
    : comm(comm)
    , first(first)
  {
    int n_ranks = 1, r = 0;
    MPI_Comm_size(comm, &n_ranks);
    MPI_Comm_rank(comm, &r);
    rank = r;
    AssertThrow(first.size() == static_cast<unsigned int>(n_ranks) + 1 && first.front() == 0 &&
                  std::is_sorted(first.begin(), first.end()),
                dealii::ExcMessage("BlockPartition: the first indices must ascend from 0, one "
                                   "per rank and the end."));
    count.resize(n_ranks);
    displacement.resize(n_ranks);
    for (int p = 0; p < n_ranks; ++p)
      {
        count[p]        = first[p + 1] - first[p];
        displacement[p] = first[p];
      }
  }

  void
  BlockPartition::gather(double *values) const
  {
    if (count.size() > 1 && first.back() > 0)
      MPI_Allgatherv(MPI_IN_PLACE,
                     0,
                     MPI_DATATYPE_NULL,
                     values,
                     count.data(),
                     displacement.data(),
                     MPI_DOUBLE,
                     comm);
  }

} // namespace FetiContact
