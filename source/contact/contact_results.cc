#include <deal.II/base/bounding_box.h>
#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/rtree.h>

#include <feticontact/base/exact_sum.h>
#include <feticontact/base/regions.h>
#include <feticontact/contact/contact_results.h>
#include <feticontact/contact/rigid_obstacle.h>

#include <algorithm>
#include <array>
#include <boost/serialization/array.hpp>
#include <boost/serialization/vector.hpp>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <set>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    /**
     * Open, stick or slip of every node from its forces and slip bounds @p bound. A node whose
     * friction acts through its vertex's keeper sticks or slips with the keeper's rows, and a
     * keeper is pressed when any node of its vertex is, since its rows carry their friction.
     */
    std::vector<ContactStatus>
    node_statuses(const std::vector<ContactNode>       &nodes,
                  const std::vector<ContactNodeResult> &results,
                  const std::vector<double>            &bound,
                  const double                          lambda_max,
                  const double                          bound_max,
                  const double                          u_max)
    {
      std::vector<bool> pressed(nodes.size());
      for (unsigned int k = 0; k < nodes.size(); ++k)
        pressed[k] = is_pressed(results[k].lambda_N, lambda_max, results[k].gap, u_max);
      for (unsigned int k = 0; k < nodes.size(); ++k)
        if (nodes[k].keeper && pressed[k])
          pressed[*nodes[k].keeper] = true;

      std::vector<ContactStatus> status(nodes.size());
      for (unsigned int k = 0; k < nodes.size(); ++k)
        {
          const unsigned int rows = nodes[k].keeper ? *nodes[k].keeper : k;
          const double force = std::hypot(results[rows].lambda_T[0], results[rows].lambda_T[1]);
          // μ = 0: a pressed node slides freely; a companion's keeper may hold only rounding.
          const double slack = nodes[k].keeper ? 1e-8 * bound_max : 0;
          status[k]          = contact_status(pressed[k], force, bound[rows], slack);
        }
      return status;
    }
  } // namespace

  namespace
  {
    /** The check of the nodes of all ranks of @p comm from those of this rank. */
    void
    reduce_over_ranks(ContactCheck &check, std::array<ExactSum, 6> &resultant, const MPI_Comm comm)
    {
      for (ExactSum &sum : resultant)
        sum.sum_over_ranks(comm);
      for (unsigned int c = 0; c < 3; ++c)
        {
          check.normal_force[c]     = resultant[c].value();
          check.tangential_force[c] = resultant[3 + c].value();
        }
      double maxima[] = {check.penetration,
                         check.cone_violation,
                         check.complementarity,
                         check.negative_normal,
                         check.pressed_slip,
                         check.slip_angle};
      Utilities::MPI::max(ArrayView<const double>(maxima, 6), comm, ArrayView<double>(maxima, 6));
      check.penetration     = maxima[0];
      check.cone_violation  = maxima[1];
      check.complementarity = maxima[2];
      check.negative_normal = maxima[3];
      check.pressed_slip    = maxima[4];
      check.slip_angle      = maxima[5];
      unsigned int counts[] = {check.n_open, check.n_stick, check.n_slip};
      Utilities::MPI::sum(ArrayView<const unsigned int>(counts, 3),
                          comm,
                          ArrayView<unsigned int>(counts, 3));
      check.n_open  = counts[0];
      check.n_stick = counts[1];
      check.n_slip  = counts[2];
    }
  } // namespace

  bool
  is_pressed(const double normal_force,
             const double largest_normal_force,
             const double gap,
             const double largest_displacement)
  {
    return normal_force > 1e-8 * largest_normal_force &&
           normal_force * largest_displacement >= gap * largest_normal_force;
  }

  ContactStatus
  contact_status(const bool   pressed,
                 const double tangential_force,
                 const double slip_bound,
                 const double slack)
  {
    if (!pressed)
      return ContactStatus::open;
    return tangential_force >= (1 - 1e-4) * slip_bound - slack ? ContactStatus::slip :
                                                                 ContactStatus::stick;
  }

  std::string
  to_string(const ContactStatus status)
  {
    switch (status)
      {
        case ContactStatus::open:
          return "open";
        case ContactStatus::stick:
          return "stick";
        default:
          return "slip";
      }
  }

  JsonObject
  ContactCheck::json() const
  {
    JsonObject kkt;
    kkt.set("penetration", penetration)
      .set("cone_violation", cone_violation)
      .set("complementarity", complementarity)
      .set("slip_angle", slip_angle)
      .set("negative_normal_force", negative_normal)
      .set("pressed_slip", pressed_slip);
    return kkt;
  }

  namespace
  {
    /** A deformed master triangle: its corners and its outward normal (area-weighted). */
    using DeformedTriangle = std::array<double, 12>;

    /**
     * The deformed triangles of zone @p z of @p triangles (the master or the slave triangles that
     * ranks list) near this rank's points @p points (within @p reach of them): from every rank,
     * the triangles it lists. Collective.
     */
    std::vector<DeformedTriangle>
    triangles_near(const unsigned int                  z,
                   const std::vector<ContactTriangle> &triangles,
                   const std::vector<Point<3>>        &points,
                   const VertexDisplacements          &u,
                   const double                        reach,
                   const MPI_Comm                      comm)
    {
      const unsigned int rank    = Utilities::MPI::this_mpi_process(comm);
      const auto         regions = Regions::of_ranks(comm, Regions::box_of(points));
      std::map<unsigned int, std::vector<DeformedTriangle>> outgoing;
      std::vector<DeformedTriangle>                         near;
      for (const auto &t : triangles)
        if (t.zone == z)
          {
            std::vector<Point<3>> corners(3);
            DeformedTriangle      deformed;
            for (unsigned int i = 0; i < 3; ++i)
              {
                corners[i] = t.points[i] + u(t.body, t.vertices[i]);
                for (unsigned int d = 0; d < 3; ++d)
                  deformed[3 * i + d] = corners[i][d];
              }
            for (unsigned int d = 0; d < 3; ++d)
              deformed[9 + d] = t.outward[d];
            const BoundingBox<3> box(corners);
            for (unsigned int r = 0; r < regions.size(); ++r)
              if (regions[r])
                {
                  BoundingBox<3> region = *regions[r];
                  region.extend(reach);
                  if (Regions::meet(region, box))
                    (r == rank ? near : outgoing[r]).push_back(deformed);
                }
          }
      for (const auto &[from, list] : Utilities::MPI::some_to_some(comm, outgoing))
        near.insert(near.end(), list.begin(), list.end());
      return near;
    }

    /**
     * The deepest of @p points behind the triangles @p triangles: its depth behind a triangle
     * whose normal projection it lies in (against the triangle's outward normal), up to @p reach
     * behind it; 0 if none is.
     */
    double
    deepest_behind(const std::vector<Point<3>>         &points,
                   const std::vector<DeformedTriangle> &triangles,
                   const double                         reach)
    {
      std::vector<std::pair<BoundingBox<3>, unsigned int>> boxes;
      const auto corner = [&](const unsigned int m, const unsigned int i) {
        return Point<3>(triangles[m][3 * i], triangles[m][3 * i + 1], triangles[m][3 * i + 2]);
      };
      for (unsigned int m = 0; m < triangles.size(); ++m)
        boxes.emplace_back(
          BoundingBox<3>(std::vector<Point<3>>{corner(m, 0), corner(m, 1), corner(m, 2)}), m);
      const auto                                           tree  = pack_rtree(boxes);
      double                                               worst = 0;
      std::vector<std::pair<BoundingBox<3>, unsigned int>> candidates;
      for (const Point<3> &p : points)
        {
          BoundingBox<3> box(std::vector<Point<3>>{p});
          box.extend(reach);
          candidates.clear();
          tree.query(boost::geometry::index::intersects(box), std::back_inserter(candidates));
          for (const auto &candidate : candidates)
            {
              const unsigned int m = candidate.second;
              const Point<3>     a = corner(m, 0), b = corner(m, 1), c = corner(m, 2);
              const Tensor<1, 3> outward({triangles[m][9], triangles[m][10], triangles[m][11]});
              Tensor<1, 3>       n_order    = cross_product_3d(b - a, c - a);
              const double       twice_area = n_order.norm();
              if (twice_area == 0)
                continue;
              n_order /= twice_area;
              const Tensor<1, 3> n = n_order * outward < 0 ? -n_order : n_order;
              const double       h = (p - a) * n;
              if (h >= 0 || -h > reach)
                continue;
              // Inside the triangle's normal projection: the three sub-areas all on its side.
              const Point<3> q       = p - h * n;
              const double   l0      = cross_product_3d(b - q, c - q) * n_order,
                           l1        = cross_product_3d(c - q, a - q) * n_order,
                           l2        = cross_product_3d(a - q, b - q) * n_order;
              const double tolerance = -1e-12 * twice_area;
              if (l0 >= tolerance && l1 >= tolerance && l2 >= tolerance)
                worst = std::max(worst, -h);
            }
        }
      return worst;
    }

    /**
     * The deepest penetration, after the load, of this rank's uncoupled vertices of body-pair
     * zone @p z (slave vertices that are no contact node of the zone: beyond the search
     * distance) into the master body: the depth behind a master triangle (deformed) whose normal
     * projection it lies in, up to @p reach behind it. Collective.
     */
    double
    uncoupled_penetration(const unsigned int         z,
                          const ContactSurfaces     &surfaces,
                          const VertexDisplacements &u,
                          const double               reach,
                          const MPI_Comm             comm)
    {
      std::vector<Point<3>> uncoupled; // deformed positions
      for (const auto &v : surfaces.uncoupled)
        if (v.zone == z)
          uncoupled.push_back(v.x + u(v.body, v.vertex));
      return deepest_behind(uncoupled,
                            triangles_near(z, surfaces.master, uncoupled, u, reach, comm),
                            reach);
    }

    /**
     * The deformed positions of the vertices of zone @p z's triangles in @p triangles that this
     * rank lists, each once.
     */
    std::vector<Point<3>>
    deformed_vertices(const unsigned int                  z,
                      const std::vector<ContactTriangle> &triangles,
                      const VertexDisplacements          &u)
    {
      std::set<std::pair<unsigned int, unsigned int>> seen; // (body, vertex)
      std::vector<Point<3>>                           points;
      for (const auto &t : triangles)
        if (t.zone == z)
          for (unsigned int i = 0; i < 3; ++i)
            if (seen.insert({t.body, t.vertices[i]}).second)
              points.push_back(t.points[i] + u(t.body, t.vertices[i]));
      return points;
    }
  } // namespace

  double
  surface_penetration(const Parameters::Contact &contact,
                      const ContactSurfaces     &surfaces,
                      const VertexDisplacements &u,
                      const double               u_max,
                      const double               largest_cell,
                      const MPI_Comm             comm)
  {
    double worst = 0;
    // Every vertex of the zone's surface, also those that start a rounding error behind it (or,
    // on a curved obstacle, inside it by up to the search distance).
    for (const auto &t : surfaces.slave)
      if (contact.zones[t.zone].rigid())
        for (unsigned int i = 0; i < 3; ++i)
          worst = std::max(worst,
                           -contact.zones[t.zone].obstacle->signed_distance(
                             t.points[i] + u(t.body, t.vertices[i])));
    // Body pairs: the slave vertices that are no contact nodes (beyond the search distance) must
    // not have passed into the master body. Contact nodes are held by their rows (the KKT check);
    // the depth searched is what the bodies can have moved against each other.
    for (unsigned int z = 0; z < contact.zones.size(); ++z)
      if (!contact.zones[z].rigid())
        worst =
          std::max(worst, uncoupled_penetration(z, surfaces, u, 2 * u_max + largest_cell, comm));
    worst = Utilities::MPI::max(worst, comm);
    return u_max > 0 ? worst / u_max : worst;
  }

  JsonObject
  MortarOverlap::json() const
  {
    return JsonObject()
      .set("slave_into_master", slave_into_master)
      .set("master_into_slave", master_into_slave);
  }

  double
  MortarOverlap::largest() const
  {
    return std::max(slave_into_master, master_into_slave);
  }

  MortarOverlap
  mortar_overlap(const std::vector<bool>   &mortar_zones,
                 const ContactSurfaces     &surfaces,
                 const VertexDisplacements &u,
                 const double               u_max,
                 const double               largest_cell,
                 const MPI_Comm             comm)
  {
    MortarOverlap overlap;
    const double  reach = 2 * u_max + largest_cell;
    for (unsigned int z = 0; z < mortar_zones.size(); ++z)
      if (mortar_zones[z])
        {
          const auto slave  = deformed_vertices(z, surfaces.slave, u);
          const auto master = deformed_vertices(z, surfaces.master, u);
          overlap.slave_into_master =
            std::max(overlap.slave_into_master,
                     deepest_behind(slave,
                                    triangles_near(z, surfaces.master, slave, u, reach, comm),
                                    reach));
          overlap.master_into_slave =
            std::max(overlap.master_into_slave,
                     deepest_behind(master,
                                    triangles_near(z, surfaces.slave, master, u, reach, comm),
                                    reach));
        }
    double maxima[] = {overlap.slave_into_master, overlap.master_into_slave};
    Utilities::MPI::max(ArrayView<const double>(maxima, 2), comm, ArrayView<double>(maxima, 2));
    const double scale        = u_max > 0 ? u_max : 1;
    overlap.slave_into_master = maxima[0] / scale;
    overlap.master_into_slave = maxima[1] / scale;
    return overlap;
  }

  double
  vertex_penetration(const Parameters::Contact &contact,
                     const unsigned int         body,
                     const Point<3>            &x,
                     const Tensor<1, 3>        &u)
  {
    double worst = 0;
    // A vertex of a body that starts outside a curved obstacle (a sphere, a cylinder) must end
    // outside. A vertex that starts in front of the body's half-spaces (rigid planes; a surface
    // chosen too small lets the body through a plane elsewhere) counts by the least of its depths
    // behind them, so that it must end behind all of them: several planes may form one convex
    // obstacle (a ridge), whose planes extend beyond it, and a vertex behind one plane's
    // extension but in front of another is outside the obstacle. (A vertex behind a plane before
    // the load, where the body reaches past the zone's surface, is not counted.)
    bool   has_planes = false, behind = false;
    double depth = std::numeric_limits<double>::infinity();
    for (const auto &zone : contact.zones)
      if (zone.rigid() && zone.body == body)
        {
          const RigidObstacle &obstacle = *zone.obstacle;
          if (!obstacle.half_space_normal())
            {
              if (obstacle.signed_distance(x) >= 0)
                worst = std::max(worst, -obstacle.signed_distance(x + u));
              continue;
            }
          has_planes = true;
          if (behind)
            continue;
          if (obstacle.signed_distance(x) < 0)
            behind = true;
          else
            depth = std::min(depth, -obstacle.signed_distance(x + u));
        }
    if (has_planes)
      worst = std::max(worst, behind ? 0. : depth);
    return worst;
  }

  std::vector<ContactNodeResult>
  evaluate_contact(const std::vector<ContactNode>                  &nodes,
                   const DualLayout                                &layout,
                   const std::function<double(const unsigned int)> &lambda,
                   const VertexDisplacements                       &u,
                   const double                                     u_max,
                   ContactCheck                                    &check,
                   const std::optional<double>                      tresca_slip_bound,
                   const MPI_Comm                                   comm)
  {
    std::vector<ContactNodeResult> results(nodes.size());
    double                         lambda_max = 0, bound_max = 0;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        const auto &node = nodes[k];
        auto       &r    = results[k];
        // The node's multipliers times σ_k are the contact force (σ_k ≠ 1 for averaged rows).
        const double sigma = layout.scale_of_node(k);
        r.lambda_N         = sigma * lambda(layout.normal_row[k]);
        if (layout.tangential_row[k] != numbers::invalid_unsigned_int)
          {
            const unsigned int first = layout.tangential_row[k];
            if (!layout.polygonal)
              {
                r.lambda_T[0] = sigma * lambda(first);
                r.lambda_T[1] = sigma * lambda(first + 1);
              }
            else
              for (unsigned int j = 0; j < layout.tangential_per_node; ++j)
                {
                  const double angle = numbers::PI * j / layout.tangential_per_node;
                  r.lambda_T[0] += sigma * std::cos(angle) * lambda(first + j);
                  r.lambda_T[1] += sigma * std::sin(angle) * lambda(first + j);
                }
          }
        const Tensor<1, 3> relative = relative_displacement(node, u);
        r.gap                       = node.gap - relative * node.n;
        // A node whose friction acts through the rows of its vertex's keeper slips along the
        // keeper's tangents.
        const ContactNode &frame = node.keeper ? nodes[*node.keeper] : node;
        r.slip[0]                = relative * frame.t1;
        r.slip[1]                = relative * frame.t2;
        lambda_max               = std::max(lambda_max, r.lambda_N);
      }
    // The slip bounds in the units of the forces: Tresca's, or μ λ_N summed over each vertex.
    std::vector<double> normal_force(nodes.size());
    for (unsigned int k = 0; k < nodes.size(); ++k)
      normal_force[k] = results[k].lambda_N;
    std::vector<double> bounds = slip_bounds(nodes, normal_force);
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        if (tresca_slip_bound && nodes[k].friction > 0)
          bounds[k] = *tresca_slip_bound;
        bound_max = std::max(bound_max, bounds[k]);
      }
    lambda_max        = Utilities::MPI::max(lambda_max, comm);
    bound_max         = Utilities::MPI::max(bound_max, comm);
    const auto status = node_statuses(nodes, results, bounds, lambda_max, bound_max, u_max);

    check = ContactCheck();
    // The resultants of the ranks' nodes as exact sums: the same bits on any number of ranks.
    std::array<ExactSum, 6> resultant;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        const auto  &node       = nodes[k];
        auto        &r          = results[k];
        const double tangential = std::hypot(r.lambda_T[0], r.lambda_T[1]);
        const double bound      = bounds[k];
        r.status                = status[k];

        check.penetration = std::max(check.penetration, std::max(-r.gap, 0.0) / u_max);
        if (bound_max > 0)
          check.cone_violation = std::max(check.cone_violation, (tangential - bound) / bound_max);
        if (lambda_max > 0)
          {
            check.complementarity =
              std::max(check.complementarity, std::abs(r.lambda_N * r.gap) / (lambda_max * u_max));
            check.negative_normal = std::max(check.negative_normal, -r.lambda_N / lambda_max);
          }
        const double slip = std::hypot(r.slip[0], r.slip[1]);
        if (r.status != ContactStatus::open)
          check.pressed_slip = std::max(check.pressed_slip, slip / u_max);
        if (r.status == ContactStatus::slip && slip > 1e-6 * u_max && tangential > 0)
          {
            // The friction force λ_T on the multiplier side points along the slip (T u): the
            // term λ_Tᵀ T u of the Lagrangian equals g ‖T u‖ at a slipping node.
            const double cosine =
              (r.lambda_T[0] * r.slip[0] + r.lambda_T[1] * r.slip[1]) / (tangential * slip);
            check.slip_angle = std::max(check.slip_angle, std::acos(std::clamp(cosine, -1.0, 1.0)));
          }
        // Forces on the slave body: −(λ_N n + λ_T1 t1 + λ_T2 t2).
        const Tensor<1, 3> on_slave_n = -r.lambda_N * node.n,
                           on_slave_t = -(r.lambda_T[0] * node.t1 + r.lambda_T[1] * node.t2);
        for (unsigned int c = 0; c < 3; ++c)
          {
            resultant[c].add(on_slave_n[c]);
            resultant[3 + c].add(on_slave_t[c]);
          }
        if (r.status == ContactStatus::open)
          ++check.n_open;
        else if (r.status == ContactStatus::stick)
          ++check.n_stick;
        else
          ++check.n_slip;
      }
    reduce_over_ranks(check, resultant, comm);
    return results;
  }

  void
  write_contact_csv(std::ostream                         &out,
                    const std::vector<ContactNode>       &nodes,
                    const std::vector<ContactNodeResult> &results,
                    const std::vector<unsigned int>      &which,
                    const bool                            header)
  {
    if (header)
      out << "zone,body,x,y,z,lambda_N,lambda_T1,lambda_T2,gap,slip_1,slip_2,status,area,pressure,"
             "weighted_gap,D_kk,n_x,n_y,n_z,t1_x,t1_y,t1_z,t2_x,t2_y,t2_z,lambda_T_x,lambda_T_y,"
             "lambda_T_z\n";
    out << std::setprecision(12);
    for (const unsigned int k : which)
      {
        const auto &n = nodes[k];
        const auto &r = results[k];
        out << n.zone + 1 << ',' << n.body + 1 << ',' << n.x[0] << ',' << n.x[1] << ',' << n.x[2]
            << ',' << r.lambda_N << ',' << r.lambda_T[0] << ',' << r.lambda_T[1] << ',' << r.gap
            << ',' << r.slip[0] << ',' << r.slip[1] << ',' << to_string(r.status) << ',' << n.area
            << ',' << r.lambda_N / n.pressure_area << ',' << n.gap * n.pressure_area << ','
            << n.pressure_area;
        // The node's frame and the tangential multiplier λ_T1 t1 + λ_T2 t2 in global coordinates.
        const dealii::Tensor<1, 3> lambda_T = r.lambda_T[0] * n.t1 + r.lambda_T[1] * n.t2;
        for (const auto *v : {&n.n, &n.t1, &n.t2, &lambda_T})
          for (unsigned int c = 0; c < 3; ++c)
            out << ',' << (*v)[c];
        out << '\n';
      }
  }
} // namespace FetiContact
