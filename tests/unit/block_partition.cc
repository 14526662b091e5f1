// BlockPartition, the split of replicated work among the ranks (run on 1 and on 3 ranks):
//  - the blocks are contiguous, in rank order, cover [0, n), and each weighs at most its share
//    of the total plus the heaviest single index;
//  - gather() gives every rank every block, exactly;
//  - the degenerate cases: no indices, fewer indices than ranks, all weight on one index.

#include <deal.II/base/mpi.h>

#include <feticontact/base/block_partition.h>

#include "test_tools.h"

#include <algorithm>
#include <random>
#include <vector>

using namespace dealii;
using namespace FetiContact;

namespace
{
  void
  check_partition(const MPI_Comm                   comm,
                  const std::vector<unsigned int> &weight,
                  const std::string               &name)
  {
    const unsigned int        n_ranks = Utilities::MPI::n_mpi_processes(comm);
    const unsigned int        rank    = Utilities::MPI::this_mpi_process(comm);
    const unsigned int        n       = weight.size();
    std::vector<unsigned int> start(n + 1, 0);
    for (unsigned int i = 0; i < n; ++i)
      start[i + 1] = start[i] + weight[i];
    const BlockPartition blocks = BlockPartition::balanced(comm, start);
    const auto          &first  = blocks.firsts();

    bool ordered = first.size() == n_ranks + 1 && first.front() == 0 && first.back() == n &&
                   std::is_sorted(first.begin(), first.end()) && blocks.begin() == first[rank] &&
                   blocks.end() == first[rank + 1];
    check(ordered,
          name + ": " + std::to_string(n_ranks) + " contiguous blocks cover [0, " +
            std::to_string(n) + ")");
    const double share    = double(start[n]) / n_ranks;
    const double heaviest = weight.empty() ? 0. : *std::max_element(weight.begin(), weight.end());
    bool         balanced = true;
    for (unsigned int p = 0; p < n_ranks && ordered; ++p)
      balanced = balanced && start[first[p + 1]] - start[first[p]] <= share + heaviest;
    check(balanced, name + ": every block weighs at most its share + the heaviest index");

    std::vector<double> values(n, -1.);
    for (unsigned int i = blocks.begin(); i < blocks.end(); ++i)
      values[i] = 0.5 * i + 1;
    blocks.gather(values.data());
    bool gathered = true;
    for (unsigned int i = 0; i < n; ++i)
      gathered = gathered && values[i] == 0.5 * i + 1;
    check(gathered, name + ": gather gives every rank every block");
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                   comm = MPI_COMM_WORLD;
  std::mt19937                     random(11);
  std::vector<unsigned int>        weight(1000);
  for (auto &w : weight)
    w = random() % 13;
  check_partition(comm, weight, "random weights 0..12");
  check_partition(comm, std::vector<unsigned int>(997, 1), "equal weights");
  check_partition(comm, {}, "no indices");
  check_partition(comm, {4, 1}, "two indices");
  std::vector<unsigned int> spike(50, 0);
  spike[17] = 100;
  check_partition(comm, spike, "all weight on one index");
  return n_failures;
}
