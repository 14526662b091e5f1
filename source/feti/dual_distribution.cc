#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <feticontact/base/mpi_tools.h>
#include <feticontact/feti/dual_distribution.h>

#include <algorithm>

namespace FetiContact
{
  using namespace dealii;

  DualDistribution::DualDistribution(const MPI_Comm                   comm,
                                     const std::vector<unsigned int> &owned_rows,
                                     const std::vector<unsigned int> &relevant_rows,
                                     const std::vector<int>          &relevant_owner,
                                     const unsigned int               n_rows,
                                     const std::vector<unsigned int> &chunk_of_owned_row)
    : comm(comm)
    , vector_layout(std::make_shared<const DistributedVector::Layout>(comm,
                                                                      owned_rows,
                                                                      n_rows,
                                                                      chunk_of_owned_row))
    , relevant(relevant_rows)
  {
    int n_ranks = 1, this_rank = 0;
    MPI_Comm_size(comm, &n_ranks);
    MPI_Comm_rank(comm, &this_rank);
    for (const unsigned int r : owned_rows)
      owned_relevant.push_back(relevant_index(r));

    // The ghosts by owner, and the owners' lists of what to send (one exchange of counts, then
    // the lists, between the ranks that share rows).
    std::vector<std::vector<unsigned int>> wanted(n_ranks);
    for (unsigned int j = 0; j < relevant.size(); ++j)
      if (relevant_owner[j] != this_rank)
        wanted[relevant_owner[j]].push_back(relevant[j]);
    std::vector<int> n_wanted(n_ranks), n_asked(n_ranks);
    for (int p = 0; p < n_ranks; ++p)
      n_wanted[p] = wanted[p].size();
    MPI_Alltoall(n_wanted.data(), 1, MPI_INT, n_asked.data(), 1, MPI_INT, comm);
    std::vector<MPI_Request>               list_requests;
    std::vector<std::vector<unsigned int>> asked(n_ranks);
    for (int p = 0; p < n_ranks; ++p)
      {
        if (n_asked[p] > 0)
          {
            asked[p].resize(n_asked[p]);
            list_requests.emplace_back();
            MPI_Irecv(asked[p].data(), n_asked[p], MPI_UNSIGNED, p, 1, comm, &list_requests.back());
          }
        if (n_wanted[p] > 0)
          {
            list_requests.emplace_back();
            MPI_Isend(
              wanted[p].data(), n_wanted[p], MPI_UNSIGNED, p, 1, comm, &list_requests.back());
          }
      }
    MPI_Waitall(list_requests.size(), list_requests.data(), MPI_STATUSES_IGNORE);
    for (int p = 0; p < n_ranks; ++p)
      {
        if (!asked[p].empty())
          {
            Exchange e{p, {}, {}};
            for (const unsigned int r : asked[p])
              {
                const auto it = std::lower_bound(owned_rows.begin(), owned_rows.end(), r);
                AssertThrow(it != owned_rows.end() && *it == r,
                            ExcMessage("DualDistribution: rank " + std::to_string(p) +
                                       " asked for row " + std::to_string(r) +
                                       ", which this rank does not own."));
                e.index.push_back(it - owned_rows.begin());
              }
            e.buffer.resize(e.index.size());
            send.push_back(std::move(e));
          }
        if (!wanted[p].empty())
          {
            Exchange e{p, {}, {}};
            for (const unsigned int r : wanted[p])
              e.index.push_back(relevant_index(r));
            e.buffer.resize(e.index.size());
            receive.push_back(std::move(e));
          }
      }
    requests.resize(send.size() + receive.size());
  }

  unsigned int
  DualDistribution::relevant_index(const unsigned int row) const
  {
    const auto it = std::lower_bound(relevant.begin(), relevant.end(), row);
    AssertThrow(it != relevant.end() && *it == row,
                ExcMessage("DualDistribution: row " + std::to_string(row) +
                           " is not relevant on this rank."));
    return it - relevant.begin();
  }

  void
  DualDistribution::import(const DistributedVector &x, Vector<double> &values) const
  {
    if (values.size() != relevant.size())
      values.reinit(relevant.size(), true);
    unsigned int n_requests = 0;
    for (const auto &e : receive)
      MPI_Irecv(
        e.buffer.data(), e.buffer.size(), MPI_DOUBLE, e.rank, 2, comm, &requests[n_requests++]);
    for (const auto &e : send)
      {
        for (unsigned int j = 0; j < e.index.size(); ++j)
          e.buffer[j] = x[e.index[j]];
        MPI_Isend(
          e.buffer.data(), e.buffer.size(), MPI_DOUBLE, e.rank, 2, comm, &requests[n_requests++]);
      }
    for (unsigned int i = 0; i < owned_relevant.size(); ++i)
      values[owned_relevant[i]] = x[i];
    MPI_Waitall(n_requests, requests.data(), MPI_STATUSES_IGNORE);
    for (const auto &e : receive)
      for (unsigned int j = 0; j < e.index.size(); ++j)
        values[e.index[j]] = e.buffer[j];
  }

  DistributedVector DualDistribution::restrict(const Vector<double> &all) const
  {
    DistributedVector x(vector_layout);
    for (unsigned int i = 0; i < x.locally_owned_size(); ++i)
      x[i] = all[x.global_index(i)];
    return x;
  }

  Vector<double>
  DualDistribution::gather(const DistributedVector &x) const
  {
    AssertThrow(x.get_layout() == vector_layout,
                ExcMessage("DualDistribution::gather: a vector of another layout."));
    if (gather_count.empty())
      {
        // Every rank's owned rows, in rank order.
        const int n_ranks = Utilities::MPI::n_mpi_processes(comm);
        const int n_owned = vector_layout->global_index.size();
        gather_count.resize(n_ranks);
        MPI_Allgather(&n_owned, 1, MPI_INT, gather_count.data(), 1, MPI_INT, comm);
        gather_displacement.assign(n_ranks + 1, 0);
        for (int p = 0; p < n_ranks; ++p)
          gather_displacement[p + 1] = gather_displacement[p] + gather_count[p];
        gathered_rows.resize(gather_displacement[n_ranks]);
        MPI_Allgatherv(vector_layout->global_index.data(),
                       n_owned,
                       MPI_UNSIGNED,
                       gathered_rows.data(),
                       gather_count.data(),
                       gather_displacement.data(),
                       MPI_UNSIGNED,
                       comm);
      }
    std::vector<double> values(gathered_rows.size());
    MPI_Allgatherv(x.begin(),
                   x.locally_owned_size(),
                   MPI_DOUBLE,
                   values.data(),
                   gather_count.data(),
                   gather_displacement.data(),
                   MPI_DOUBLE,
                   comm);
    Vector<double> all(vector_layout->n_global);
    for (std::size_t j = 0; j < values.size(); ++j)
      all[gathered_rows[j]] = values[j];
    return all;
  }

  namespace
  {
    template <typename Exchange>
    std::size_t
    n_values(const std::vector<Exchange> &exchanges)
    {
      std::size_t n = 0;
      for (const auto &e : exchanges)
        n += e.index.size();
      return n;
    }
  } // namespace

  std::size_t
  DualDistribution::n_sent() const
  {
    return n_values(send);
  }

  std::size_t
  DualDistribution::n_received() const
  {
    return n_values(receive);
  }
} // namespace FetiContact
