#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/mpi.templates.h>

#include <feticontact/feti/dual_space.h>

#include <algorithm>
#include <map>
#include <numeric>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    /** The owned rows by chunk, then number: the order of their entries. */
    std::vector<unsigned int>
    owned_order(const std::vector<unsigned int> &rows, const std::vector<unsigned int> &chunk)
    {
      std::vector<unsigned int> order(rows.size());
      std::iota(order.begin(), order.end(), 0u);
      std::sort(order.begin(), order.end(), [&](const unsigned int a, const unsigned int b) {
        return chunk[a] != chunk[b] ? chunk[a] < chunk[b] : rows[a] < rows[b];
      });
      return order;
    }
  } // namespace

  DualSpace::DualSpace(const MPI_Comm                   comm,
                       const std::vector<unsigned int> &owned_rows,
                       const std::vector<unsigned int> &chunk_of_owned_row,
                       const std::vector<unsigned int> &ghost_rows,
                       const std::vector<int>          &ghost_owner,
                       const unsigned int               n_rows)
    : comm(comm)
  {
    AssertDimension(owned_rows.size(), chunk_of_owned_row.size());
    AssertDimension(ghost_rows.size(), ghost_owner.size());
    const std::vector<unsigned int> order = owned_order(owned_rows, chunk_of_owned_row);
    std::vector<unsigned int>       key(order.size()), chunk(order.size());
    for (unsigned int i = 0; i < order.size(); ++i)
      {
        key[i]   = owned_rows[order[i]];
        chunk[i] = chunk_of_owned_row[order[i]];
      }
    unsigned long long n_owned = key.size(), first = 0;
    MPI_Exscan(&n_owned, &first, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      first = 0;

    // The index of every ghost row, from its owner.
    std::map<unsigned int, std::vector<unsigned int>> wanted;
    for (unsigned int j = 0; j < ghost_rows.size(); ++j)
      wanted[ghost_owner[j]].push_back(ghost_rows[j]);
    std::vector<unsigned int> by_number(key.size());
    std::iota(by_number.begin(), by_number.end(), 0u);
    std::sort(by_number.begin(), by_number.end(), [&](const unsigned int a, const unsigned int b) {
      return key[a] < key[b];
    });
    const auto owned_local = [&](const unsigned int row) {
      const auto it =
        std::lower_bound(by_number.begin(),
                         by_number.end(),
                         row,
                         [&](const unsigned int i, const unsigned int r) { return key[i] < r; });
      return it != by_number.end() && key[*it] == row ? *it : numbers::invalid_unsigned_int;
    };
    std::map<unsigned int, std::vector<types::global_dof_index>> answers;
    for (const auto &[rank, rows] : Utilities::MPI::some_to_some(comm, wanted))
      for (const unsigned int r : rows)
        {
          const unsigned int i = owned_local(r);
          AssertThrow(i != numbers::invalid_unsigned_int,
                      ExcMessage("DualSpace: rank " + std::to_string(rank) + " asked for row " +
                                 std::to_string(r) + ", which this rank does not own."));
          answers[rank].push_back(first + i);
        }
    const auto answered = Utilities::MPI::some_to_some(comm, answers);
    std::vector<std::pair<unsigned int, types::global_dof_index>> ghosts;
    for (const auto &[rank, rows] : wanted)
      {
        const auto &index = answered.at(rank);
        for (unsigned int j = 0; j < rows.size(); ++j)
          ghosts.emplace_back(rows[j], index[j]);
      }
    IndexSet ghost_set(n_rows);
    for (const auto &[row, index] : ghosts)
      ghost_set.add_index(index);
    ghost_set.compress();
    row_partitioner = std::make_shared<const ReproduciblePartitioner>(
      comm, first, n_rows, ghost_set, std::move(key), chunk);

    // Row numbers of the owned and ghost entries, and their local indices.
    std::vector<std::pair<unsigned int, unsigned int>> known;
    for (unsigned int i = 0; i < row_partitioner->locally_owned_size(); ++i)
      known.emplace_back(row_partitioner->key(i), i);
    for (const auto &[row, index] : ghosts)
      known.emplace_back(row, row_partitioner->global_to_local(index));
    std::sort(known.begin(), known.end());
    for (const auto &[row, local] : known)
      {
        known_rows.push_back(row);
        known_local.push_back(local);
      }
  }

  DualVector
  DualSpace::vector() const
  {
    return DualVector(row_partitioner);
  }

  unsigned int
  DualSpace::local_index(const unsigned int row) const
  {
    const auto it = std::lower_bound(known_rows.begin(), known_rows.end(), row);
    return it != known_rows.end() && *it == row ? known_local[it - known_rows.begin()] :
                                                  numbers::invalid_unsigned_int;
  }

  unsigned int
  DualSpace::owned_index(const unsigned int row) const
  {
    const unsigned int i = local_index(row);
    return i < n_owned() ? i : numbers::invalid_unsigned_int;
  }

  types::global_dof_index
  DualSpace::global_index(const unsigned int row) const
  {
    const unsigned int i = local_index(row);
    AssertThrow(i != numbers::invalid_unsigned_int,
                ExcMessage("DualSpace: row " + std::to_string(row) +
                           " is neither owned nor a ghost on this rank."));
    return row_partitioner->local_to_global(i);
  }

  DualVector DualSpace::restrict(const Vector<double> &all) const
  {
    DualVector x = vector();
    for (unsigned int i = 0; i < n_owned(); ++i)
      x.local_element(i) = all[row(i)];
    return x;
  }

  Vector<double>
  DualSpace::gather(const DualVector &x) const
  {
    const auto rows   = Utilities::MPI::all_gather(comm, row_partitioner->owned_keys());
    const auto values = Utilities::MPI::all_gather(
      comm, std::vector<double>(x.begin(), x.begin() + x.locally_owned_size()));
    Vector<double> all(row_partitioner->size());
    for (unsigned int p = 0; p < rows.size(); ++p)
      for (unsigned int j = 0; j < rows[p].size(); ++j)
        all[rows[p][j]] = values[p][j];
    return all;
  }
} // namespace FetiContact
