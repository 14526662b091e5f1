#include <deal.II/base/mpi.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/base/mpi_tools.h>
#include <feticontact/contact/body_pair_search.h>
#include <feticontact/contact/contact_nodes.h>
#include <feticontact/contact/obstacle_nodes.h>

#include <cmath>
#include <functional>
#include <map>
#include <tuple>

namespace FetiContact::ContactSearch
{
  using namespace dealii;

  namespace
  {
    /**
     * A Dirichlet vertex (@p prescribed components) stays a contact node only under a roller
     * condition tangential to the contact surface; returns false otherwise.
     */
    bool
    orient_for_roller(ContactNode &node, const Body::Prescribed &prescribed)
    {
      // A Dirichlet node is not a contact node, unless its prescribed components are
      // orthogonal to the normal: a symmetry (roller) condition tangential to the contact
      // surface, as on the symmetry planes of a quarter or half model. With friction the
      // tangent t2 is then the prescribed axis: its row acts on no free DoF (contact rows
      // skip the slave's prescribed components, and on the master side the components along
      // them), λ_T2 stays 0, and the disc ‖λ_T‖ ≤ g becomes the
      // interval |λ_T1| ≤ g along the free tangent t1 (the symmetric solution has no
      // tangential force across the symmetry plane).
      bool         conflicts = false;
      unsigned int axis      = numbers::invalid_unsigned_int;
      for (unsigned int d = 0; d < 3; ++d)
        if (prescribed[d])
          {
            if (std::abs(node.n[d]) > 1e-12)
              conflicts = true;
            axis = d;
          }
      if (conflicts)
        return false;
      if (axis != numbers::invalid_unsigned_int)
        {
          Tensor<1, 3> e;
          e[axis] = 1;
          node.t2 = e - (e * node.n) * node.n;
          node.t2 /= node.t2.norm();
          node.t1 = cross_product_3d(node.t2, node.n);
        }
      return true;
    }
  } // namespace

  std::string
  point_text(const Tensor<1, 3> &p)
  {
    // (+ 0.0 prints −0 as 0.)
    return '(' + InputParsing::number_text(p[0] + 0.0) + ", " +
           InputParsing::number_text(p[1] + 0.0) + ", " + InputParsing::number_text(p[2] + 0.0) +
           ')';
  }

  std::string
  touching_text(const Surface &slave, const unsigned int v)
  {
    return InputParsing::number_text(slave.touching_depth(v)) + " (" +
           InputParsing::number_text(touching_fraction) + " of the local mesh size " +
           InputParsing::number_text(slave.local_edge(v)) + ")";
  }

  void
  add_over_ranks(const std::vector<unsigned int *> &counts, const MPI_Comm comm)
  {
    std::vector<unsigned int> values;
    for (const unsigned int *count : counts)
      values.push_back(*count);
    Utilities::MPI::sum(values, comm, values);
    for (unsigned int i = 0; i < counts.size(); ++i)
      *counts[i] = values[i];
  }


  std::optional<ContactNode>
  ZoneSide::start_node(const unsigned int vertex) const
  {
    const SurfaceVertex &x = slave.vertex.at(vertex);
    if (!x.home || (x.copies.prescribed[0] && x.copies.prescribed[1] && x.copies.prescribed[2]))
      return {};
    ContactNode node;
    node.zone          = z;
    node.body          = zone.body;
    node.vertex        = vertex;
    node.x             = x.x;
    node.copies        = x.copies;
    node.friction      = zone.friction_coefficient;
    node.area          = slave.area.at(vertex);
    node.pressure_area = node.area;
    return node;
  }

  void
  ZoneSide::finish_node(ContactNode &node, std::vector<ContactNode> &nodes) const
  {
    const Body::Prescribed &prescribed = node.copies.prescribed;
    // A node of a body pair on a symmetry plane (a roller condition): the mean normal of its
    // triangles, of which the model has only those on one side of the plane, is turned into
    // the plane, as the mirrored triangles would turn it.
    if (node.on_body())
      {
        Tensor<1, 3> n = node.n;
        for (unsigned int d = 0; d < 3; ++d)
          if (prescribed[d])
            n[d] = 0;
        if (n != node.n && n.norm() > 1e-3)
          node.n = n / n.norm();
      }
    std::tie(node.t1, node.t2) = tangent_basis(node.n);
    if (!orient_for_roller(node, prescribed))
      return;
    nodes.push_back(node);
  }
} // namespace FetiContact::ContactSearch

namespace FetiContact
{
  using namespace dealii;
  using namespace ContactSearch;

  std::pair<Tensor<1, 3>, Tensor<1, 3>>
  tangent_basis(const Tensor<1, 3> &n)
  {
    // Start from the coordinate axis least aligned with n.
    unsigned int axis = 0;
    for (unsigned int d = 1; d < 3; ++d)
      if (std::abs(n[d]) < std::abs(n[axis]))
        axis = d;
    Tensor<1, 3> a;
    a[axis]         = 1;
    Tensor<1, 3> t1 = a - (a * n) * n;
    t1 /= t1.norm();
    return {t1, cross_product_3d(n, t1)};
  }

  namespace
  {
    /**
     * The vertices that lie on the surfaces of several zones (an edge or corner where two
     * obstacles meet, a body pair beside a plane). Every zone keeps its normal row, so the
     * vertex stays out of every obstacle; of rigid planes with the same normal only the one
     * with the smallest gap stays (it alone can bind: their gaps differ by a constant). The
     * tangential rows would repeat the normal rows of the other zones (the tangent plane of one
     * plane contains the normal of the other), and the multipliers would not be unique: one node
     * of the vertex, the keeper (the first with friction), keeps the tangential directions
     * orthogonal to every normal of the vertex (the edge's direction at an edge, none at a corner)
     * and the others keep none (t1 = t2 = 0: rows without entries, whose multipliers stay 0). The
     * friction of a node whose rows would act on the same motion as the keeper's (both on rigid
     * obstacles, or both against one master vertex) acts through the keeper's rows, whose slip
     * bound is the sum of those zones' μ λ_N (slip_bounds()); where a body pair meets a rigid
     * plane, only the keeper's zone has friction along the edge.
     */
    void
    combine_shared_vertices(std::vector<ContactNode> &nodes)
    {
      std::map<std::pair<unsigned int, unsigned int>, std::vector<unsigned int>> of_vertex;
      for (unsigned int k = 0; k < nodes.size(); ++k)
        of_vertex[{nodes[k].body, nodes[k].vertex}].push_back(k);
      std::vector<bool> dropped(nodes.size(), false);
      for (const auto &[vertex, ks] : of_vertex)
        {
          if (ks.size() < 2)
            continue;
          for (unsigned int a = 0; a < ks.size(); ++a)
            for (unsigned int b = a + 1; b < ks.size(); ++b)
              if (!dropped[ks[a]] && !dropped[ks[b]] && !nodes[ks[a]].on_body() &&
                  !nodes[ks[b]].on_body() && nodes[ks[a]].n * nodes[ks[b]].n > 1 - 1e-8)
                dropped[nodes[ks[a]].gap <= nodes[ks[b]].gap ? ks[b] : ks[a]] = true;
          // An orthonormal basis of the span of the normals kept at the vertex.
          std::vector<Tensor<1, 3>> basis;
          for (const unsigned int k : ks)
            if (!dropped[k])
              {
                Tensor<1, 3> v = nodes[k].n;
                for (const auto &e : basis)
                  v -= (v * e) * e;
                if (v.norm() > 1e-8)
                  basis.push_back(v / v.norm());
              }
          // The keeper of the tangential rows: the first node with friction (only nodes with
          // μ > 0 have tangential rows), else the first.
          unsigned int keeper = numbers::invalid_unsigned_int;
          for (const unsigned int k : ks)
            if (!dropped[k] && (keeper == numbers::invalid_unsigned_int ||
                                (nodes[keeper].friction == 0 && nodes[k].friction > 0)))
              keeper = k;
          for (const unsigned int k : ks)
            {
              if (dropped[k])
                continue;
              ContactNode &node = nodes[k];
              if (k != keeper || basis.size() == 3)
                node.t1 = node.t2 = Tensor<1, 3>();
              else if (basis.size() == 2)
                {
                  node.t1 = cross_product_3d(basis[0], basis[1]);
                  node.t1 /= node.t1.norm();
                  node.t2 = Tensor<1, 3>();
                }
              // The keeper's rows carry this node's friction only if they act on the same
              // motion: both on a rigid obstacle, or both against the same master vertex.
              if (k != keeper && basis.size() < 3 && node.master == nodes[keeper].master)
                node.keeper = keeper;
            }
        }
      std::vector<unsigned int> new_index(nodes.size(), numbers::invalid_unsigned_int);
      unsigned int              kept = 0;
      for (unsigned int k = 0; k < nodes.size(); ++k)
        if (!dropped[k])
          {
            new_index[k]  = kept;
            nodes[kept++] = nodes[k];
          }
      nodes.resize(kept);
      for (auto &node : nodes)
        if (node.keeper)
          node.keeper = new_index[*node.keeper];
    }
  } // namespace

  std::vector<ContactNode>
  find_contact_nodes(const std::vector<std::unique_ptr<Body>> &bodies,
                     const Parameters::Contact                &contact,
                     ContactSurfaces                          *surfaces,
                     std::vector<ZoneReport>                  *reports,
                     const bool                                home_nodes)
  {
    std::vector<std::vector<std::vector<unsigned int>>> parts(bodies.size());
    const std::function<const std::vector<std::vector<unsigned int>> &(const Body &)>
      parts_of_vertex = [&](const Body &body) -> const std::vector<std::vector<unsigned int>> & {
      if (parts[body.index].empty())
        parts[body.index] = body.parts_of_mesh_vertices();
      return parts[body.index];
    };
    // Shared: every rank finds the nodes of its home vertices (the bodies' cells distributed).
    const bool     shared = home_nodes && !bodies.empty() && bodies.front()->distributed();
    const MPI_Comm comm   = shared ? bodies.front()->mesh_comm() : MPI_COMM_SELF;
    std::vector<ContactNode> nodes;
    for (unsigned int z = 0; z < contact.zones.size(); ++z)
      {
        const auto            &zone    = contact.zones[z];
        const std::string      where   = "Contact zone " + std::to_string(z + 1) + ": ";
        const Body            &body    = *bodies[zone.body];
        const BoundarySelector surface = resolved_surface(body, zone.surface, where + "Surface: ");
        const Share            share   = shared ? Share::home_rings : Share::whole;
        const Surface          slave = collect_surface(body, surface, parts_of_vertex(body), share);
        if (surfaces != nullptr)
          slave.append_to(surfaces->slave, z, zone.body);

        const ZoneSide side{
          z, zone, body, slave, where, surfaces, parts_of_vertex, surface, share, comm};
        ZoneReport         report;
        const unsigned int first = nodes.size();
        if (zone.rigid())
          add_obstacle_nodes(side, *zone.obstacle, nodes, report);
        else
          {
            add_body_pair_nodes(side, bodies, nodes, report);
            if (surfaces != nullptr)
              add_uncoupled_vertices(side, nodes, first, surfaces->uncoupled);
          }
        report.n_nodes = nodes.size() - first;
        add_over_ranks({&report.n_nodes,
                        &report.n_uncovered,
                        &report.n_partly_covered,
                        &report.n_overlapping,
                        &report.n_touching},
                       comm);
        require(report.n_nodes > 0,
                where + "the surface <" + zone.surface.name() + "> of body '" +
                  body.parameters.name +
                  "' has no contact node (all its vertices are Dirichlet vertices" +
                  (report.n_uncovered > 0 ? ", or have no master surface opposite them)." : ")."));
        if (reports != nullptr)
          reports->push_back(report);
      }
    combine_shared_vertices(nodes);
    return nodes;
  }

  Tensor<1, 3>
  relative_displacement(const ContactNode &node, const VertexDisplacements &u)
  {
    Tensor<1, 3> relative = u(node.body, node.vertex);
    for (const auto &m : node.master)
      relative -= m.weight * u(m.body, m.vertex);
    return relative;
  }

  Point<3>
  master_point(const ContactNode &node)
  {
    Point<3> y;
    for (const auto &m : node.master)
      y += m.weight * m.y;
    return y;
  }

  std::vector<double>
  slip_bounds(const std::vector<ContactNode> &nodes, const std::vector<double> &normal_force)
  {
    std::vector<double> g(nodes.size());
    for (unsigned int k = 0; k < nodes.size(); ++k)
      g[k] = nodes[k].friction * std::max(normal_force[k], 0.0);
    for (unsigned int k = 0; k < nodes.size(); ++k)
      if (nodes[k].keeper)
        g[*nodes[k].keeper] += g[k];
    return g;
  }

  std::size_t
  memory_consumption(const std::vector<ContactNode> &nodes, const ContactSurfaces &surfaces)
  {
    std::size_t bytes =
      nodes.capacity() * sizeof(ContactNode) +
      (surfaces.slave.capacity() + surfaces.master.capacity()) * sizeof(ContactTriangle) +
      surfaces.uncoupled.capacity() * sizeof(ContactSurfaces::Vertex);
    for (const ContactNode &node : nodes)
      {
        bytes += node.master.capacity() * sizeof(MasterPoint) +
                 node.copies.parts.capacity() * sizeof(unsigned int);
        for (const MasterPoint &m : node.master)
          bytes += m.copies.parts.capacity() * sizeof(unsigned int);
      }
    return bytes;
  }
} // namespace FetiContact
