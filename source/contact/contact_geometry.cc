#include <deal.II/grid/grid_tools.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/contact/contact_geometry.h>

#include <cmath>
#include <map>
#include <set>

namespace FetiContact
{
  using namespace dealii;

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
     * The vertices of the boundary faces of @p mesh in @p surface, with the area-weighted sum of
     * the outward normals of those faces, the area lumped at each vertex, and the mean edge
     * length of the faces.
     */
    struct Surface
    {
      std::map<unsigned int, Tensor<1, 3>>     normal_sum;
      std::map<unsigned int, double>           area; ///< a third of each adjacent triangle
      double                                   mean_edge = 0;
      std::vector<std::array<unsigned int, 3>> triangles;
    };

    Surface
    collect_surface(const Triangulation<3> &mesh, const BoundarySelector &surface)
    {
      Surface      s;
      unsigned int n_edges = 0;
      for (const auto &cell : mesh.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && surface.contains(*face))
            {
              const Point<3> a = face->vertex(0), b = face->vertex(1), c = face->vertex(2);
              Tensor<1, 3>   area_normal = 0.5 * cross_product_3d(b - a, c - a);
              if (area_normal * (face->center() - cell->center()) < 0)
                area_normal = -area_normal;
              for (const unsigned int v : face->vertex_indices())
                {
                  s.normal_sum[face->vertex_index(v)] += area_normal;
                  s.area[face->vertex_index(v)] += area_normal.norm() / 3;
                }
              s.triangles.push_back(
                {{face->vertex_index(0), face->vertex_index(1), face->vertex_index(2)}});
              s.mean_edge += a.distance(b) + b.distance(c) + c.distance(a);
              n_edges += 3;
            }
      if (n_edges > 0)
        s.mean_edge /= n_edges;
      return s;
    }

    std::string
    point_text(const Tensor<1, 3> &p)
    {
      // (+ 0.0 prints −0 as 0.)
      return '(' + InputParsing::number_text(p[0] + 0.0) + ", " +
             InputParsing::number_text(p[1] + 0.0) + ", " + InputParsing::number_text(p[2] + 0.0) +
             ')';
    }

    /**
     * A rigid plane's normal must point out of the obstacle, towards the body: against the
     * (area-weighted) outer normal of the zone's surface. Otherwise InputError names the zone
     * and the node whose outer normal points most along the plane's normal.
     */
    void
    check_plane_faces_body(const Surface                 &slave,
                           const Body                    &body,
                           const Parameters::ContactZone &zone,
                           const std::string             &where)
    {
      Tensor<1, 3> total;
      double       worst        = -2;
      unsigned int worst_vertex = 0;
      double       magnitude    = 0; // Σ |area normals|: |total| below it is a curved surface
      for (const auto &[vertex, normal_sum] : slave.normal_sum)
        {
          total += normal_sum;
          magnitude += normal_sum.norm();
          const double c = normal_sum * zone.plane_normal / normal_sum.norm();
          if (c > worst)
            {
              worst        = c;
              worst_vertex = vertex;
            }
        }
      // Nearly perpendicular (within about 6°): the plane cannot face this surface. Only for a
      // surface whose normals point one way (|Σ n| ≥ 0.7 Σ|n|, arcs below about 160°): the mean
      // normal of a half cylinder or a closed surface says nothing about where it faces.
      const double cosine = total.norm() > 0 ? total * zone.plane_normal / total.norm() : 0;
      require(total.norm() < 0.7 * magnitude || std::abs(cosine) > 0.1,
              where + "the plane normal " + point_text(zone.plane_normal) +
                " is (nearly) perpendicular to the surface <" + zone.surface.name() +
                "> of body '" + body.parameters.name + "', whose mean outer normal is " +
                point_text(total / std::max(total.norm(), 1e-300)) + " (cosine " +
                InputParsing::number_text(cosine) +
                "): a rigid plane must face the surface it is paired with (a plane normal "
                "against that outer normal, or the surface that faces the plane).");
      require(total * zone.plane_normal < 0,
              where + "the plane normal " + point_text(zone.plane_normal) + " points into body '" +
                body.parameters.name + "': the outer normal of its surface <" +
                zone.surface.name() + "> is " +
                point_text(slave.normal_sum.at(worst_vertex) /
                           slave.normal_sum.at(worst_vertex).norm()) +
                " at the node at " + point_text(body.mesh.get_vertices()[worst_vertex]) +
                ". The plane normal must point out of the obstacle, towards the body (here " +
                point_text(-zone.plane_normal) + "?).");
    }

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
              if (!dropped[ks[a]] && !dropped[ks[b]] && !nodes[ks[a]].master &&
                  !nodes[ks[b]].master && nodes[ks[a]].n * nodes[ks[b]].n > 1 - 1e-8)
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

  namespace
  {
    /** The gap and normal of @p node towards a rigid plane: χ(x) is its orthogonal projection. */
    void
    place_on_plane(ContactNode                   &node,
                   const Parameters::ContactZone &zone,
                   const Surface                 &slave,
                   const std::string             &where)
    {
      // χ(x): the orthogonal projection of x on the plane, so the critical direction
      // is the plane's normal (towards the obstacle) for every node.
      const double distance = (node.x - zone.plane_point) * zone.plane_normal;
      require(distance >= -1e-10 * slave.mean_edge,
              where + "the node at " + point_text(node.x) +
                " lies inside the rigid obstacle (initial penetration " +
                InputParsing::number_text(-distance) + ").");
      node.gap = std::max(distance, 0.0);
      node.n   = -zone.plane_normal;
    }

    /**
     * The gap and normal of @p node towards the master surface: χ(x) is the master vertex
     * opposite x along its outer normal @p outer; the meshes must match node to node.
     */
    void
    place_opposite_master(ContactNode                   &node,
                          const Tensor<1, 3>            &outer,
                          const Surface                 &slave,
                          const Surface                 &master,
                          const Body                    &body,
                          const Body                    *master_body,
                          const Parameters::ContactZone &zone,
                          const std::string             &where)
    {
      // χ(x): the master vertex opposite x along the outer normal.
      double       best_offset = std::numeric_limits<double>::max();
      unsigned int best        = numbers::invalid_unsigned_int;
      for (const auto &[mv, unused] : master.normal_sum)
        {
          const Tensor<1, 3> d      = master_body->mesh.get_vertices()[mv] - node.x;
          const double       along  = d * outer;
          const double       offset = (d - along * outer).norm();
          if (offset < best_offset)
            {
              best_offset = offset;
              best        = mv;
            }
        }
      require(best != numbers::invalid_unsigned_int && best_offset <= 1e-6 * slave.mean_edge,
              where + "the node at " + point_text(node.x) + " of body '" + body.parameters.name +
                "' has no node of the master surface of body '" + master_body->parameters.name +
                "' opposite it: the meshes of the two surfaces do not match (they must "
                "be conforming node to node).");
      node.master          = std::make_pair(zone.master_body, best);
      const Tensor<1, 3> d = master_body->mesh.get_vertices()[best] - node.x;
      const Tensor<1, 3> master_outer =
        master.normal_sum.at(best) / master.normal_sum.at(best).norm();
      require(master_outer * outer < 0,
              where + "the master surface <" + zone.master_surface.name() + "> of body '" +
                master_body->parameters.name +
                "' faces away from the slave surface: at the node at " + point_text(node.x) +
                " of body '" + body.parameters.name +
                "' the outer normals of the two surfaces are " + point_text(outer) + " and " +
                point_text(master_outer) +
                " (they must point towards each other; is the master surface the "
                "other side of its body?).");
      require(d * outer >= -1e-8 * slave.mean_edge,
              where + "the node at " + point_text(node.x) + " of body '" + body.parameters.name +
                "' lies inside body '" + master_body->parameters.name + "' (initial penetration " +
                InputParsing::number_text(-(d * outer)) +
                " along its outer normal): the bodies overlap before any load.");
      if (d.norm() > 1e-8 * slave.mean_edge)
        {
          node.n   = d / d.norm();
          node.gap = d.norm();
        }
      else
        {
          node.n   = outer;
          node.gap = 0;
        }
    }

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
      // skip prescribed components), λ_T2 stays 0, and the disc ‖λ_T‖ ≤ g becomes the
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

  std::vector<ContactNode>
  find_contact_nodes(const std::vector<std::unique_ptr<Body>> &bodies,
                     const Parameters::Contact                &contact,
                     std::vector<ContactTriangle>             *triangles)
  {
    std::vector<ContactNode> nodes;
    for (unsigned int z = 0; z < contact.zones.size(); ++z)
      {
        const auto       &zone  = contact.zones[z];
        const std::string where = "Contact zone " + std::to_string(z + 1) + ": ";
        const Body       &body  = *bodies[zone.body];
        BoundarySelector  surface(zone.surface);
        try
          {
            surface.resolve(body.mesh, body.parameters.name);
          }
        catch (const InputError &e)
          {
            throw InputError(where + "Surface: " + e.what());
          }
        const Surface slave = collect_surface(body.mesh, surface);
        if (triangles != nullptr)
          for (const auto &t : slave.triangles)
            triangles->push_back({z, zone.body, t});

        Surface     master;
        const Body *master_body = nullptr;
        if (zone.type == Parameters::ContactZone::Type::body)
          {
            master_body = bodies[zone.master_body].get();
            BoundarySelector master_surface(zone.master_surface);
            master_surface.resolve(master_body->mesh, master_body->parameters.name);
            master = collect_surface(master_body->mesh, master_surface);
          }

        if (zone.type == Parameters::ContactZone::Type::rigid_plane)
          check_plane_faces_body(slave, body, zone, where);

        unsigned int n_in_zone = 0;
        for (const auto &[vertex, normal_sum] : slave.normal_sum)
          {
            const auto prescribed = body.prescribed.find(vertex);
            if (prescribed != body.prescribed.end() && prescribed->second[0] &&
                prescribed->second[1] && prescribed->second[2])
              continue; // clamped
            ContactNode node;
            node.zone                = z;
            node.body                = zone.body;
            node.vertex              = vertex;
            node.x                   = body.mesh.get_vertices()[vertex];
            node.friction            = zone.friction_coefficient;
            node.area                = slave.area.at(vertex);
            const Tensor<1, 3> outer = normal_sum / normal_sum.norm();
            if (zone.type == Parameters::ContactZone::Type::rigid_plane)
              {
                place_on_plane(node, zone, slave, where);
              }
            else
              {
                place_opposite_master(node, outer, slave, master, body, master_body, zone, where);
              }
            std::tie(node.t1, node.t2) = tangent_basis(node.n);
            if (prescribed != body.prescribed.end() && !orient_for_roller(node, prescribed->second))
              continue;
            nodes.push_back(node);
            ++n_in_zone;
          }
        require(n_in_zone > 0,
                where + "the surface <" + zone.surface.name() + "> of body '" +
                  body.parameters.name +
                  "' has no contact node (all its vertices are Dirichlet vertices).");
      }
    combine_shared_vertices(nodes);
    return nodes;
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
} // namespace FetiContact
