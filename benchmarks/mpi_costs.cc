// mpi_costs [--rounds R] [--calls C] [--sizes V1,V2,...]: under mpirun -np P, the costs that the
// parallel model of doc/performance.md takes from this machine: the time of one global reduction
// as the distributed dual vectors make it (MPI_Allreduce of one double, for minima and maxima, and
// ExactSum::sum_over_ranks, the exact sums: 536 bytes of integers), and the time of a message of
// V doubles between two ranks (half a ping-pong between ranks 0 and P/2, the others idle). Each is
// the median over R rounds of C calls after a barrier. Rank 0 prints CSV rows:
// np,operation,values,seconds (run by parallel_model.py).

#include <deal.II/base/mpi.h>

#include <feticontact/base/exact_sum.h>

#include "benchmark_tools.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using namespace FetiContact;

namespace
{
  /** The median over @p rounds of the time per call of @p f (@p calls calls after a barrier). */
  template <typename F>
  double
  median_seconds(const MPI_Comm comm, const unsigned int rounds, const unsigned int calls, F &&f)
  {
    std::vector<double> t;
    for (unsigned int r = 0; r < rounds; ++r)
      {
        MPI_Barrier(comm);
        const auto start = std::chrono::steady_clock::now();
        for (unsigned int c = 0; c < calls; ++c)
          f();
        const double local =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / calls;
        t.push_back(dealii::Utilities::MPI::max(local, comm));
      }
    return BenchmarkTools::median(t);
  }
} // namespace

int
main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);
  const auto line =
    BenchmarkTools::parse_command_line(argc, argv, {"--rounds", "--calls", "--sizes"});
  if (line.help || !line.ok)
    {
      std::cerr << "usage: mpi_costs [--rounds R] [--calls C] [--sizes V1,V2,...]\n";
      MPI_Finalize();
      return line.help ? 0 : 2;
    }
  const unsigned int        rounds = line.positive("--rounds", 9);
  const unsigned int        calls  = line.positive("--calls", 2000);
  std::vector<unsigned int> sizes{1, 100, 1000, 10000, 100000};
  if (const auto it = line.values.find("--sizes"); it != line.values.end())
    {
      sizes.clear();
      std::stringstream list(it->second);
      std::string       item;
      while (std::getline(list, item, ','))
        sizes.push_back(BenchmarkTools::parse_positive(item));
    }
  if (rounds == 0 || calls == 0 || std::count(sizes.begin(), sizes.end(), 0u) > 0)
    {
      MPI_Finalize();
      return 2;
    }
  const MPI_Comm comm = MPI_COMM_WORLD;
  const int      rank = dealii::Utilities::MPI::this_mpi_process(comm);
  const int      np   = dealii::Utilities::MPI::n_mpi_processes(comm);
  const auto     row  = [&](const std::string &operation, const unsigned int values, double s) {
    if (rank == 0)
      std::cout << np << ',' << operation << ',' << values << ',' << s << std::endl;
  };

  double x = rank + 1;
  row("allreduce_double", 1, median_seconds(comm, rounds, calls, [&]() {
        double y;
        MPI_Allreduce(&x, &y, 1, MPI_DOUBLE, MPI_MAX, comm);
        x = y - np; // depends on the result: no call can be skipped
      }));
  row("exact_sum", 67, median_seconds(comm, rounds, calls, [&]() {
        ExactSum s;
        s.add(x);
        s.sum_over_ranks(comm);
        x = s.value() * 1e-300 + rank;
      }));
  if (np > 1)
    for (const unsigned int v : sizes)
      {
        std::vector<double> buffer(v, 1.0);
        const int           partner = rank == 0 ? np / 2 : 0;
        const bool          active  = rank == 0 || rank == np / 2;
        const unsigned int  n       = std::max(10u, std::min(calls, 20000000u / std::max(v, 1u)));
        const double        t       = median_seconds(comm, rounds, n, [&]() {
          if (!active)
            return;
          if (rank == 0)
            {
              MPI_Send(buffer.data(), v, MPI_DOUBLE, partner, 0, comm);
              MPI_Recv(buffer.data(), v, MPI_DOUBLE, partner, 0, comm, MPI_STATUS_IGNORE);
            }
          else
            {
              MPI_Recv(buffer.data(), v, MPI_DOUBLE, partner, 0, comm, MPI_STATUS_IGNORE);
              MPI_Send(buffer.data(), v, MPI_DOUBLE, partner, 0, comm);
            }
        });
        row("message", v, t / 2);
      }
  MPI_Finalize();
  return 0;
}
