#include <deal.II/base/mpi.h>

#include <feticontact/base/mpi_tools.h>
#include <feticontact/feti/equality_constraints.h>

#include <algorithm>
#include <array>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <unordered_map>
#include <utility>

namespace FetiContact
{
  using namespace dealii;

  void
  DualRows::add_row(const std::vector<DualRowEntry> &row, const double rhs)
  {
    entries.insert(entries.end(), row.begin(), row.end());
    row_start.push_back(entries.size());
    c.push_back(rhs);
    number.push_back(n_all++);
  }

  void
  DualRows::add_row_of(const DualRows &other, const unsigned int r, const unsigned int row_number)
  {
    entries.insert(entries.end(),
                   other.entries.begin() + other.row_start[r],
                   other.entries.begin() + other.row_start[r + 1]);
    row_start.push_back(entries.size());
    c.push_back(other.c[r]);
    number.push_back(row_number);
  }

  void
  DualRows::append(const DualRows &other)
  {
    AssertThrow(std::uint64_t(n_all) + other.n_all < numbers::invalid_unsigned_int,
                ExcMessage("The rows of B exceed the range of an unsigned int."));
    for (auto set : other.held_together)
      {
        for (unsigned int &r : set)
          r += n_rows();
        held_together.push_back(std::move(set));
      }
    held_by.insert(held_by.end(), other.held_by.begin(), other.held_by.end());
    for (unsigned int r = 0; r < other.n_rows(); ++r)
      add_row_of(other, r, n_all + other.number[r]);
    n_all += other.n_all;
  }

  void
  DualRows::append(const DualRows &other, const unsigned int first, const unsigned int last)
  {
    for (unsigned int r = first; r < last; ++r)
      add_row_of(other, r, n_all++);
  }

  DualRows
  DualRows::rows_touching(const std::function<bool(unsigned int)> &touches,
                          const bool                               keep_empty) const
  {
    std::vector<bool> keep(n_rows(), false);
    for (unsigned int r = 0; r < n_rows(); ++r)
      {
        keep[r] = keep_empty && row_start[r] == row_start[r + 1];
        for (unsigned int k = row_start[r]; !keep[r] && k < row_start[r + 1]; ++k)
          keep[r] = touches(entries[k].subdomain);
      }
    for (const auto &set : held_together)
      if (std::any_of(set.begin(), set.end(), [&](const unsigned int r) { return keep[r]; }))
        for (const unsigned int r : set)
          keep[r] = true;
    DualRows                  kept;
    std::vector<unsigned int> index(n_rows(), numbers::invalid_unsigned_int);
    for (unsigned int r = 0; r < n_rows(); ++r)
      if (keep[r])
        {
          index[r] = kept.n_rows();
          kept.add_row_of(*this, r, number[r]);
        }
    kept.n_all = n_all;
    for (unsigned int i = 0; i < held_together.size(); ++i)
      if (!held_together[i].empty() && keep[held_together[i].front()])
        {
          kept.held_together.emplace_back();
          for (const unsigned int r : held_together[i])
            kept.held_together.back().push_back(index[r]);
          kept.held_by.push_back(held_by[i]);
        }
    return kept;
  }

  namespace
  {
    /**
     * Appends to @p rows the rows of the vertices whose lowest holder is subdomain @p s, a
     * group per vertex, and to @p groups (body, body vertex, first row) of each group.
     */
    void
    add_vertex_rows(const Subdomain           &s,
                    const bool                 dirichlet_rows,
                    DualRows                  &rows,
                    std::vector<unsigned int> &groups)
    {
      std::vector<DualRowEntry> row;
      for (const auto &[body_vertex, v] : s.reported_vertices())
        {
          groups.insert(groups.end(), {s.body.index, body_vertex, rows.n_rows()});
          const std::vector<unsigned int> h = s.holders(v);
          for (unsigned int c = 0; c < 3; ++c)
            {
              const auto &prescribed = s.prescribed[s.vertex_dofs[v][c]];
              if (prescribed)
                {
                  if (dirichlet_rows)
                    for (const unsigned int holder : h)
                      rows.add_row({{holder, body_vertex, c, 1.0}}, *prescribed);
                  continue;
                }
              for (unsigned int j = 1; j < h.size(); ++j)
                {
                  const double scale = 1.0 / std::sqrt(double(j) * (j + 1));
                  row.clear();
                  for (unsigned int k = 0; k < j; ++k)
                    row.push_back({h[k], body_vertex, c, scale});
                  row.push_back({h[j], body_vertex, c, -scale * j});
                  rows.add_row(row, 0.0);
                }
            }
        }
    }
  } // namespace

  DualRows
  build_equality_rows(const MPI_Comm                  comm,
                      const std::vector<Subdomain *> &owned,
                      const bool                      dirichlet_rows)
  {
    // This rank's rows, a group per vertex: (body, body vertex, first row) of each group.
    DualRows                  mine;
    std::vector<unsigned int> groups;
    for (const Subdomain *s : owned)
      add_vertex_rows(*s, dirichlet_rows, mine, groups);
    const auto all = Utilities::MPI::all_gather(comm, std::make_pair(groups, mine));

    // Every group of every rank, ordered by (body, body vertex); a vertex has one group.
    std::vector<std::array<unsigned int, 4>> order; // (body, vertex, rank, group)
    for (unsigned int r = 0; r < all.size(); ++r)
      for (unsigned int g = 0; g < all[r].first.size() / 3; ++g)
        order.push_back({{all[r].first[3 * g], all[r].first[3 * g + 1], r, g}});
    std::sort(order.begin(), order.end());
    DualRows rows;
    for (const auto &[body, vertex, r, g] : order)
      {
        const auto &[rank_groups, rank_rows] = all[r];
        const unsigned int last =
          3 * g + 5 < rank_groups.size() ? rank_groups[3 * g + 5] : rank_rows.n_rows();
        rows.append(rank_rows, rank_groups[3 * g + 2], last);
      }
    return rows;
  }

  namespace
  {
    /**
     * The key of the vertex of every group (body, body vertex, first row) in @p groups, with the
     * vertices of all bodies one after the other, and the number of all keys (over the ranks).
     */
    std::pair<std::vector<std::uint64_t>, std::uint64_t>
    vertex_keys(const MPI_Comm comm, const std::vector<unsigned int> &groups)
    {
      const unsigned int n_groups = groups.size() / 3;
      unsigned int       n_bodies = 0;
      for (unsigned int g = 0; g < n_groups; ++g)
        n_bodies = std::max(n_bodies, groups[3 * g] + 1);
      n_bodies = Utilities::MPI::max(n_bodies, comm);
      std::vector<unsigned int> n_vertices(n_bodies, 0);
      for (unsigned int g = 0; g < n_groups; ++g)
        n_vertices[groups[3 * g]] = std::max(n_vertices[groups[3 * g]], groups[3 * g + 1] + 1);
      Utilities::MPI::max(n_vertices, comm, n_vertices);
      std::vector<std::uint64_t> key_offset(n_bodies + 1, 0);
      for (unsigned int b = 0; b < n_bodies; ++b)
        key_offset[b + 1] = key_offset[b] + n_vertices[b];
      std::vector<std::uint64_t> keys(n_groups);
      for (unsigned int g = 0; g < n_groups; ++g)
        keys[g] = key_offset[groups[3 * g]] + groups[3 * g + 1];
      return {std::move(keys), key_offset.back()};
    }

    /**
     * The number among all rows of the first row of every group (body, body vertex, first row)
     * in @p groups, which has @p n_rows rows in all (number_by_keys() with the vertices of all
     * bodies as keys). Returns the first numbers and the number of all rows.
     */
    std::pair<std::vector<std::uint64_t>, std::uint64_t>
    number_groups(const MPI_Comm                   comm,
                  const std::vector<unsigned int> &groups,
                  const unsigned int               n_rows)
    {
      const unsigned int        n_groups = groups.size() / 3;
      const auto                keyed    = vertex_keys(comm, groups);
      std::vector<unsigned int> sizes(n_groups);
      for (unsigned int g = 0; g < n_groups; ++g)
        sizes[g] = (g + 1 < n_groups ? groups[3 * g + 5] : n_rows) - groups[3 * g + 2];
      return number_by_keys(comm, keyed.first, sizes);
    }
  } // namespace

  std::pair<std::vector<std::uint64_t>, std::uint64_t>
  number_by_keys(const MPI_Comm                    comm,
                 const std::vector<std::uint64_t> &keys,
                 const std::vector<unsigned int>  &sizes)
  {
    // The ranges of the counting ranks split the keys of all items in equal numbers (keys
    // cluster: the contact nodes of a surface are a small part of the vertices): every rank
    // offers up to 64 of its keys, evenly spaced, and the ranges end at every (number of
    // offers / ranks)-th of all offers.
    const unsigned int         n_ranks = Utilities::MPI::n_mpi_processes(comm);
    std::vector<std::uint64_t> mine;
    for (unsigned int g = 0; g < keys.size(); ++g)
      if (sizes[g] > 0)
        mine.push_back(keys[g]);
    std::sort(mine.begin(), mine.end());
    std::vector<std::uint64_t> offers;
    const std::size_t          n_offers = std::min<std::size_t>(64, mine.size());
    for (std::size_t i = 0; i < n_offers; ++i)
      offers.push_back(mine[i * mine.size() / n_offers]);
    std::vector<std::uint64_t> all_offers = MPITools::all_gather(comm, offers);
    std::sort(all_offers.begin(), all_offers.end());
    std::vector<std::uint64_t> ends; // a key ≥ ends[r] is counted by a rank above r
    for (unsigned int r = 1; r < n_ranks && !all_offers.empty(); ++r)
      ends.push_back(all_offers[r * all_offers.size() / n_ranks]);
    const auto counter = [&](const std::uint64_t key) {
      return static_cast<unsigned int>(std::upper_bound(ends.begin(), ends.end(), key) -
                                       ends.begin());
    };

    // Every item's key and size to the rank that counts its range.
    std::map<unsigned int, std::vector<std::array<std::uint64_t, 2>>> counted;
    for (unsigned int g = 0; g < keys.size(); ++g)
      if (sizes[g] > 0)
        counted[counter(keys[g])].push_back({{keys[g], sizes[g]}});
    std::vector<std::array<std::uint64_t, 3>> ranged; // (key, size, rank of the item)
    for (const auto &[from, list] : Utilities::MPI::some_to_some(comm, counted))
      for (const auto &[key, size] : list)
        ranged.push_back({{key, size, from}});
    std::sort(ranged.begin(), ranged.end());
    std::uint64_t n_counted = 0, before = 0;
    for (const auto &item : ranged)
      n_counted += item[1];
    MPI_Exscan(&n_counted, &before, 1, MPI_UINT64_T, MPI_SUM, comm);
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      before = 0;
    std::map<unsigned int, std::vector<std::array<std::uint64_t, 2>>> firsts;
    for (const auto &[key, size, from] : ranged)
      {
        firsts[from].push_back({{key, before}});
        before += size;
      }
    std::unordered_map<std::uint64_t, std::uint64_t> first_of_key;
    for (const auto &[from, list] : Utilities::MPI::some_to_some(comm, firsts))
      for (const auto &[key, first] : list)
        first_of_key[key] = first;
    std::vector<std::uint64_t> first(keys.size(), 0);
    for (unsigned int g = 0; g < keys.size(); ++g)
      if (sizes[g] > 0)
        first[g] = first_of_key.at(keys[g]);
    return {std::move(first), Utilities::MPI::sum(n_counted, comm)};
  }

  DualRows
  DualRows::merged(const std::vector<const DualRows *> &parts)
  {
    std::vector<std::array<unsigned int, 3>> order; // (number, part, row)
    for (unsigned int j = 0; j < parts.size(); ++j)
      for (unsigned int r = 0; r < parts[j]->n_rows(); ++r)
        order.push_back({{parts[j]->number[r], j, r}});
    std::sort(order.begin(), order.end());
    DualRows                               rows;
    std::vector<std::vector<unsigned int>> index(parts.size());
    for (unsigned int j = 0; j < parts.size(); ++j)
      index[j].resize(parts[j]->n_rows());
    for (const auto &[number, j, r] : order)
      {
        AssertThrow(rows.n_rows() == 0 || rows.number.back() < number,
                    ExcMessage("DualRows::merged: row " + std::to_string(number) + " twice."));
        index[j][r] = rows.n_rows();
        rows.add_row_of(*parts[j], r, number);
      }
    for (unsigned int j = 0; j < parts.size(); ++j)
      {
        rows.n_all = std::max(rows.n_all, parts[j]->n_all);
        for (unsigned int i = 0; i < parts[j]->held_together.size(); ++i)
          {
            rows.held_together.emplace_back();
            for (const unsigned int r : parts[j]->held_together[i])
              rows.held_together.back().push_back(index[j][r]);
            rows.held_by.push_back(parts[j]->held_by.empty() ? numbers::invalid_unsigned_int :
                                                               parts[j]->held_by[i]);
          }
      }
    return rows;
  }

  DualRows
  DualRows::sent_to_ranks(const MPI_Comm                   comm,
                          const std::vector<unsigned int> &owner,
                          const bool                       to_all) const
  {
    const unsigned int     n_ranks = Utilities::MPI::n_mpi_processes(comm);
    const unsigned int     rank    = Utilities::MPI::this_mpi_process(comm);
    std::set<unsigned int> ranks;
    if (to_all)
      for (unsigned int r = 0; r < n_ranks; ++r)
        ranks.insert(r);
    else
      for (const DualRowEntry &entry : entries)
        ranks.insert(owner[entry.subdomain]);
    std::map<unsigned int, DualRows> outgoing;
    for (const unsigned int r : ranks)
      if (r != rank)
        outgoing[r] = to_all ?
                        *this :
                        rows_touching([&](const unsigned int s) { return owner[s] == r; }, false);
    const DualRows kept =
      rows_touching([&](const unsigned int s) { return to_all || owner[s] == rank; }, false);
    const auto                    incoming = Utilities::MPI::some_to_some(comm, outgoing);
    std::vector<const DualRows *> parts{&kept};
    for (const auto &[from, rows] : incoming)
      parts.push_back(&rows);
    DualRows all = merged(parts);
    all.n_all    = Utilities::MPI::max(n_all, comm);
    return all;
  }

  DualRows
  build_local_equality_rows(const MPI_Comm                   comm,
                            const std::vector<Subdomain *>  &owned,
                            const std::vector<unsigned int> &owner,
                            const bool                       dirichlet_rows)
  {
    const unsigned int this_rank = Utilities::MPI::this_mpi_process(comm);
    // This rank's rows, a group per vertex: (body, body vertex, first row) of each group.
    DualRows                  mine;
    std::vector<unsigned int> groups;
    for (const Subdomain *s : owned)
      add_vertex_rows(*s, dirichlet_rows, mine, groups);
    const auto [first, n_all] = number_groups(comm, groups, mine.n_rows());
    AssertThrow(n_all < numbers::invalid_unsigned_int,
                ExcMessage("The rows of B_E exceed the range of an unsigned int."));

    // Every row numbered, kept if it touches this rank's subdomains, and sent to the ranks of
    // the other subdomains it touches.
    DualRows                         numbered;
    std::map<unsigned int, DualRows> outgoing;
    std::vector<unsigned int>        ranks;
    const unsigned int               n_groups = groups.size() / 3;
    for (unsigned int g = 0; g < n_groups; ++g)
      {
        const unsigned int begin = groups[3 * g + 2];
        const unsigned int end   = g + 1 < n_groups ? groups[3 * g + 5] : mine.n_rows();
        for (unsigned int r = begin; r < end; ++r)
          {
            ranks.clear();
            for (unsigned int k = mine.row_start[r]; k < mine.row_start[r + 1]; ++k)
              ranks.push_back(owner[mine.entries[k].subdomain]);
            std::sort(ranks.begin(), ranks.end());
            ranks.erase(std::unique(ranks.begin(), ranks.end()), ranks.end());
            const unsigned int number = first[g] + (r - begin);
            for (const unsigned int p : ranks)
              (p == this_rank ? numbered : outgoing[p]).add_row_of(mine, r, number);
          }
      }
    std::vector<std::pair<unsigned int, const DualRows *>> sources{{this_rank, &numbered}};
    const auto incoming = Utilities::MPI::some_to_some(comm, outgoing);
    for (const auto &[from, rows] : incoming)
      if (from != this_rank)
        sources.emplace_back(from, &rows);

    // All of them by number.
    std::vector<std::array<unsigned int, 3>> order; // (number, source, row)
    for (unsigned int j = 0; j < sources.size(); ++j)
      for (unsigned int r = 0; r < sources[j].second->n_rows(); ++r)
        order.push_back({{sources[j].second->number[r], j, r}});
    std::sort(order.begin(), order.end());
    DualRows rows;
    for (const auto &[number, j, r] : order)
      rows.add_row_of(*sources[j].second, r, number);
    rows.n_all = n_all;
    return rows;
  }
} // namespace FetiContact
