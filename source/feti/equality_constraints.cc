#include <deal.II/base/mpi.h>

#include <feticontact/feti/equality_constraints.h>

#include <algorithm>
#include <array>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>
#include <cmath>

namespace FetiContact
{
  using namespace dealii;

  void
  DualRows::add_row(const std::vector<DualRowEntry> &row, const double rhs)
  {
    entries.insert(entries.end(), row.begin(), row.end());
    row_start.push_back(entries.size());
    c.push_back(rhs);
  }

  void
  DualRows::append(const DualRows &other)
  {
    for (auto set : other.held_together)
      {
        for (unsigned int &r : set)
          r += n_rows();
        held_together.push_back(std::move(set));
      }
    append(other, 0, other.n_rows());
  }

  void
  DualRows::append(const DualRows &other, const unsigned int first, const unsigned int last)
  {
    for (unsigned int r = first; r < last; ++r)
      add_row(std::vector<DualRowEntry>(other.entries.begin() + other.row_start[r],
                                        other.entries.begin() + other.row_start[r + 1]),
              other.c[r]);
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
} // namespace FetiContact
