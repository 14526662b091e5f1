#include <feticontact/feti/equality_constraints.h>

#include <algorithm>
#include <cmath>

namespace FetiContact
{
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
    for (unsigned int r = 0; r < other.n_rows(); ++r)
      add_row(std::vector<DualRowEntry>(other.entries.begin() + other.row_start[r],
                                        other.entries.begin() + other.row_start[r + 1]),
              other.c[r]);
  }

  DualRows
  build_equality_rows(const std::vector<std::unique_ptr<Body>> &bodies,
                      const std::vector<unsigned int>          &first_subdomain,
                      const bool                                dirichlet_rows)
  {
    DualRows rows;
    for (const auto &body : bodies)
      {
        // The subdomains that hold each vertex, in increasing order.
        auto holders = parts_of_vertices(body->mesh, body->partition);
        for (auto &h : holders)
          for (auto &p : h)
            p += first_subdomain[body->index];
        std::vector<DualRowEntry> row;
        for (unsigned int v = 0; v < holders.size(); ++v)
          {
            const auto &h = holders[v];
            if (h.empty())
              continue;
            const auto it = body->prescribed.find(v);
            for (unsigned int c = 0; c < 3; ++c)
              {
                const bool is_prescribed = it != body->prescribed.end() && it->second[c];
                if (is_prescribed)
                  {
                    if (dirichlet_rows)
                      for (const unsigned int s : h)
                        rows.add_row({{s, v, c, 1.0}}, *it->second[c]);
                    continue;
                  }
                for (unsigned int j = 1; j < h.size(); ++j)
                  {
                    const double scale = 1.0 / std::sqrt(double(j) * (j + 1));
                    row.clear();
                    for (unsigned int k = 0; k < j; ++k)
                      row.push_back({h[k], v, c, scale});
                    row.push_back({h[j], v, c, -scale * j});
                    rows.add_row(row, 0.0);
                  }
              }
          }
      }
    return rows;
  }
} // namespace FetiContact
