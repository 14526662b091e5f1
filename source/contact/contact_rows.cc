#include <deal.II/base/numbers.h>

#include <feticontact/contact/contact_rows.h>

#include <cmath>

namespace FetiContact
{
  using namespace dealii;

  DualRows
  build_contact_rows(const std::vector<ContactNode>           &nodes,
                     const std::vector<std::unique_ptr<Body>> &bodies,
                     const std::vector<unsigned int>          &first_subdomain,
                     DualLayout                               &layout,
                     const unsigned int                        polygon_directions)
  {
    std::vector<std::vector<std::vector<unsigned int>>> parts(bodies.size());
    for (const auto &body : bodies)
      parts[body->index] = parts_of_vertices(body->mesh, body->partition);
    const auto copy = [&](unsigned int body, unsigned int vertex) {
      return first_subdomain[body] + parts[body][vertex].front();
    };

    const auto row_of = [&](const ContactNode &node, const Tensor<1, 3> &v) {
      std::vector<DualRowEntry> row;
      const unsigned int        s = copy(node.body, node.vertex);
      for (unsigned int c = 0; c < 3; ++c)
        if (v[c] != 0)
          row.push_back({s, node.vertex, c, v[c]});
      if (node.master)
        {
          const auto [mb, mv]   = *node.master;
          const unsigned int sm = copy(mb, mv);
          for (unsigned int c = 0; c < 3; ++c)
            if (v[c] != 0)
              row.push_back({sm, mv, c, -v[c]});
        }
      return row;
    };

    DualRows rows;
    layout.normal_row.assign(nodes.size(), 0);
    layout.tangential_row.assign(nodes.size(), numbers::invalid_unsigned_int);
    layout.tangential_per_node = polygon_directions > 0 ? polygon_directions : 2;
    layout.polygonal           = polygon_directions > 0;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      if (nodes[k].friction > 0)
        {
          layout.tangential_row[k] = rows.n_rows();
          if (polygon_directions == 0)
            {
              rows.add_row(row_of(nodes[k], nodes[k].t1), 0.0);
              rows.add_row(row_of(nodes[k], nodes[k].t2), 0.0);
            }
          else
            for (unsigned int j = 0; j < polygon_directions; ++j)
              {
                const double angle = numbers::PI * j / polygon_directions;
                rows.add_row(row_of(nodes[k],
                                    std::cos(angle) * nodes[k].t1 + std::sin(angle) * nodes[k].t2),
                             0.0);
              }
        }
    layout.n_tangential = rows.n_rows();
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        layout.normal_row[k] = rows.n_rows();
        rows.add_row(row_of(nodes[k], nodes[k].n), nodes[k].gap);
      }
    layout.n_normal = nodes.size();
    return rows;
  }
} // namespace FetiContact
