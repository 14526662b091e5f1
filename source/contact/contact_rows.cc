#include <deal.II/base/mpi.h>
#include <deal.II/base/numbers.h>

#include <feticontact/contact/contact_rows.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <optional>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    /**
     * One set of @p rows held together (DualRows::held_together) per slave vertex: the rows of
     * its nodes, held by the vertex's home subdomain (the lowest of its copies, first_subdomain
     * of the body added). A node's rows are the blocks of its constraint set, the nodes of a
     * vertex add up their slip bounds at its keeper, and the home subdomain's rank holds the
     * slave vertex, whatever the master side.
     */
    void
    hold_rows_together(const std::vector<ContactNode>  &nodes,
                       const std::vector<unsigned int> &first_subdomain,
                       const DualLayout                &layout,
                       DualRows                        &rows)
    {
      std::map<std::pair<unsigned int, unsigned int>, std::vector<unsigned int>> of_vertex;
      std::map<std::pair<unsigned int, unsigned int>, unsigned int>              home;
      for (unsigned int k = 0; k < nodes.size(); ++k)
        {
          const std::pair<unsigned int, unsigned int> vertex{nodes[k].body, nodes[k].vertex};
          auto                                       &set = of_vertex[vertex];
          set.push_back(layout.normal_row[k]);
          if (layout.tangential_row[k] != numbers::invalid_unsigned_int)
            for (unsigned int j = 0; j < layout.tangential_per_node; ++j)
              set.push_back(layout.tangential_row[k] + j);
          home[vertex] = first_subdomain[nodes[k].body] + nodes[k].copies.parts.front();
        }
      for (auto &[vertex, set] : of_vertex)
        {
          rows.held_together.push_back(std::move(set));
          rows.held_by.push_back(home[vertex]);
        }
    }
  } // namespace

  DualRows
  build_contact_rows(const std::vector<ContactNode>  &nodes,
                     const std::vector<unsigned int> &first_subdomain,
                     DualLayout                      &layout,
                     const unsigned int               polygon_directions,
                     const bool                       average)
  {
    // The copies a row acts on: the lowest-numbered one, or all of them (averaged).
    const auto n_copies = [&](const VertexCopies &copies) -> unsigned int {
      return average ? copies.parts.size() : 1;
    };

    // A row (B u)_k = v·u_slave − v·u_master ≤ c_k has no entries on prescribed components:
    // their displacement p is known and moves to the right-hand side, c_k − v_c p_c (slave) or
    // c_k + v_c p_c (master). find_contact_nodes admits prescribed slave components only
    // orthogonal to n, so on the slave side only a tangential row along a symmetry plane's roller
    // condition loses entries (and becomes empty); on the master side a clamped vertex keeps the
    // row consistent with the primal treatment, which eliminates those DoFs.
    // σ_k: the averaged row v·(Σu_slave/p − Σ_j w_j Σu_j/q_j) has the length
    // |v|√(1/p + Σ_j w_j²/q_j) against |v|√(1 + Σ_j w_j²) of the row on single copies (node to
    // node: √(1/p + 1/q) against √2; √(1/p) against 1 without a master).
    const auto scale_of = [&](const ContactNode &node) {
      if (!node.on_body())
        return std::sqrt(static_cast<double>(n_copies(node.copies)));
      double averaged = 1.0 / n_copies(node.copies), single = 1;
      for (const auto &m : node.master)
        {
          averaged += m.weight * m.weight / n_copies(m.copies);
          single += m.weight * m.weight;
        }
      return std::sqrt(single / averaged);
    };
    const auto add_row = [&](DualRows           &rows,
                             const ContactNode  &node,
                             const Tensor<1, 3> &v,
                             double              c_k) {
      std::vector<DualRowEntry> row;
      const double              sigma    = scale_of(node);
      const auto                add_side = [&](const unsigned int  body,
                                const unsigned int  vertex,
                                const VertexCopies &copies,
                                const double        sign,
                                const Tensor<1, 3> &w) {
        const unsigned int p = n_copies(copies);
        for (unsigned int c = 0; c < 3; ++c)
          if (w[c] != 0)
            {
              if (const auto prescribed_value = copies.prescribed[c])
                c_k -= sign * w[c] * *prescribed_value;
              else
                for (unsigned int j = 0; j < p; ++j)
                  row.push_back(
                    {first_subdomain[body] + copies.parts[j], vertex, c, sigma * sign * w[c] / p});
            }
      };
      add_side(node.body, node.vertex, node.copies, 1.0, v);
      // Along a prescribed axis of the slave vertex (a roller condition) the support takes the
      // slave's force: the master side acts along the other components of v only, so that no
      // force reaches the master without its reaction on the slave (the row along that axis,
      // t2 of a roller node, is then empty and its multiplier stays 0).
      Tensor<1, 3> w = v;
      for (unsigned int c = 0; c < 3; ++c)
        if (node.copies.prescribed[c])
          w[c] = 0;
      for (const auto &m : node.master)
        add_side(m.body, m.vertex, m.copies, -m.weight, w);
      rows.add_row(row, sigma * c_k);
    };

    DualRows rows;
    layout.normal_row.assign(nodes.size(), 0);
    layout.tangential_row.assign(nodes.size(), numbers::invalid_unsigned_int);
    layout.node_scale.resize(nodes.size());
    for (unsigned int k = 0; k < nodes.size(); ++k)
      layout.node_scale[k] = scale_of(nodes[k]);
    layout.tangential_per_node = polygon_directions > 0 ? polygon_directions : 2;
    layout.polygonal           = polygon_directions > 0;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      if (nodes[k].friction > 0)
        {
          layout.tangential_row[k] = rows.n_rows();
          if (polygon_directions == 0)
            {
              add_row(rows, nodes[k], nodes[k].t1, 0.0);
              add_row(rows, nodes[k], nodes[k].t2, 0.0);
            }
          else
            for (unsigned int j = 0; j < polygon_directions; ++j)
              {
                const double angle = numbers::PI * j / polygon_directions;
                add_row(rows,
                        nodes[k],
                        std::cos(angle) * nodes[k].t1 + std::sin(angle) * nodes[k].t2,
                        0.0);
              }
        }
    layout.n_tangential = rows.n_rows();
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        layout.normal_row[k] = rows.n_rows();
        add_row(rows, nodes[k], nodes[k].n, nodes[k].gap);
      }
    layout.n_normal = nodes.size();
    hold_rows_together(nodes, first_subdomain, layout, rows);
    return rows;
  }

  DualRows
  build_shared_contact_rows(const MPI_Comm                   comm,
                            const std::vector<ContactNode>  &nodes,
                            const std::vector<unsigned int> &first_subdomain,
                            const std::vector<unsigned int> &owner,
                            DualLayout                      &layout,
                            const unsigned int               polygon_directions,
                            const bool                       average,
                            const bool                       to_all)
  {
    DualRows rows = build_contact_rows(nodes, first_subdomain, layout, polygon_directions, average);

    // A node's place among the nodes of all ranks, and among those with friction: nodes are in
    // the order of zones and slave vertices, a node per zone and vertex.
    std::uint64_t n_vertices = 0;
    for (const ContactNode &node : nodes)
      n_vertices = std::max<std::uint64_t>(n_vertices, node.vertex + 1);
    n_vertices = Utilities::MPI::max(n_vertices, comm);
    std::vector<std::uint64_t> keys(nodes.size());
    std::vector<unsigned int>  ones(nodes.size(), 1), tangential(nodes.size(), 0);
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        keys[k] = nodes[k].zone * n_vertices + nodes[k].vertex;
        if (layout.tangential_row[k] != numbers::invalid_unsigned_int)
          tangential[k] = layout.tangential_per_node;
      }
    const auto [node_number, n_nodes]           = number_by_keys(comm, keys, ones);
    const auto [first_tangential, n_tangential] = number_by_keys(comm, keys, tangential);
    AssertThrow(n_nodes + n_tangential < numbers::invalid_unsigned_int,
                ExcMessage("The contact rows exceed the range of an unsigned int."));

    // The rows and the layout renumbered: the rows of this rank's nodes among those of all.
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        if (layout.tangential_row[k] != numbers::invalid_unsigned_int)
          for (unsigned int j = 0; j < layout.tangential_per_node; ++j)
            rows.number[layout.tangential_row[k] + j] = first_tangential[k] + j;
        rows.number[layout.normal_row[k]] = n_tangential + node_number[k];
        if (layout.tangential_row[k] != numbers::invalid_unsigned_int)
          layout.tangential_row[k] = first_tangential[k];
        layout.normal_row[k] = n_tangential + node_number[k];
      }
    rows.n_all          = n_tangential + n_nodes;
    layout.n_tangential = n_tangential;
    layout.n_normal     = n_nodes;
    return rows.sent_to_ranks(comm, owner, to_all);
  }

  HeldContactNodes
  hold_contact_nodes(const std::vector<ContactNode>                &nodes,
                     const DualLayout                              &layout,
                     const std::function<bool(const unsigned int)> &holds_node)
  {
    const bool       laid_out = layout.normal_row.size() == nodes.size();
    HeldContactNodes held;
    held.layout = layout;
    held.layout.normal_row.clear();
    held.layout.tangential_row.clear();
    held.layout.node_scale.clear();
    std::vector<unsigned int> held_index(nodes.size(), numbers::invalid_unsigned_int);
    for (unsigned int k = 0; k < nodes.size(); ++k)
      if (holds_node(k))
        {
          held_index[k] = held.nodes.size();
          held.nodes.push_back(nodes[k]);
          if (!laid_out)
            continue;
          held.layout.normal_row.push_back(layout.normal_row[k]);
          held.layout.tangential_row.push_back(layout.tangential_row[k]);
          held.layout.node_scale.push_back(layout.scale_of_node(k));
        }
    for (ContactNode &node : held.nodes)
      if (node.keeper)
        {
          AssertThrow(held_index[*node.keeper] != numbers::invalid_unsigned_int,
                      ExcMessage("hold_contact_nodes: the keeper of a held node is not held."));
          node.keeper = held_index[*node.keeper];
        }
    return held;
  }
} // namespace FetiContact
