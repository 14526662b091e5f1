#include <deal.II/base/mpi.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/base/mpi_tools.h>
#include <feticontact/contact/contact_state.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace FetiContact
{
  using namespace dealii;

  void
  for_each_held_row(const DualVector                                            &x,
                    const std::function<void(const unsigned int, const double)> &f)
  {
    // The row numbers are the keys of the dual vectors' partitioner (DualSpace).
    const ReproduciblePartitioner &rows = *ReproducibleReductions::partitioner_of(x);
    for (unsigned int i = 0; i < x.locally_owned_size(); ++i)
      f(rows.key(i), x.local_element(i));
  }

  void
  ContactState::find(const std::vector<std::unique_ptr<Body>> &bodies,
                     const Parameters::Contact                &contact,
                     const MPI_Comm                            comm)
  {
    found   = find_contact_nodes(bodies, contact, &contact_surfaces, &zone_reports, true);
    n_found = Utilities::MPI::sum(static_cast<unsigned int>(found.size()), comm);
    mortar_zones.clear();
    for (const ZoneReport &r : zone_reports)
      mortar_zones.push_back(r.discretization == "mortar");
  }

  void
  ContactState::report_zones(ConditionalOStream &pcout) const
  {
    for (unsigned int z = 0; z < zone_reports.size(); ++z)
      {
        const ZoneReport &r = zone_reports[z];
        if (r.n_touching > 0)
          pcout << "Contact zone " << z + 1 << ": " << r.n_touching
                << " nodes start inside by less than "
                << InputParsing::number_text(touching_fraction)
                << " of the local mesh size: they touch (initial gap 0)" << std::endl;
        if (r.discretization == "rigid plane")
          continue;
        pcout << "Contact zone " << z + 1 << ": " << r.discretization << ", " << r.n_nodes
              << " nodes";
        if (r.discretization == "mortar")
          pcout << " (" << r.n_partly_covered << " partly covered, " << r.n_overlapping
                << " overlapping initially); " << r.n_uncovered
                << " slave vertices without a master opposite them; " << r.n_segments
                << " segments within the search distance "
                << InputParsing::number_text(r.search_distance) << " m";
        if (r.discretization == "rigid obstacle")
          pcout << " (" << r.n_overlapping << " inside it initially); " << r.n_uncovered
                << " vertices farther than the search distance";
        pcout << std::endl;
      }
  }

  void
  ContactState::check_bodies_held(const std::vector<std::unique_ptr<Body>> &bodies,
                                  const Parameters::Contact                &contact,
                                  const MPI_Comm                            comm) const
  {
    // Contact nodes per body, as slave or as master, over all ranks.
    std::vector<unsigned int> touching(bodies.size());
    for (const ContactNode &node : found)
      {
        ++touching[node.body];
        for (const MasterPoint &m : node.master)
          ++touching[m.body];
      }
    MPI_Allreduce(MPI_IN_PLACE, touching.data(), touching.size(), MPI_UNSIGNED, MPI_SUM, comm);
    for (const auto &body : bodies)
      {
        if (touching[body->index] > 0 || !in_contact(contact, body->index))
          continue;
        const FreeRigidMotions free = body->free_rigid_motions();
        if (free.n() > 0)
          throw InputError("Body '" + body->parameters.name +
                           "' is not held: its prescribed displacements "
                           "leave " +
                           std::to_string(free.n()) + " rigid body motion(s) free (" + free.text() +
                           "), and its contact zones found no contact node on it" +
                           uncoupled_vertices_text() + ".");
      }
  }

  std::string
  ContactState::uncoupled_vertices_text() const
  {
    std::string text;
    for (unsigned int z = 0; z < zone_reports.size(); ++z)
      {
        const ZoneReport &r = zone_reports[z];
        if (r.n_uncovered == 0 || r.discretization == "rigid plane")
          continue;
        text += ". In contact zone " + std::to_string(z + 1) + ", " +
                std::to_string(r.n_uncovered) + " slave vertices have " +
                (r.discretization == "rigid obstacle" ? "no obstacle" : "no master") +
                " within the search distance " + InputParsing::number_text(r.search_distance) +
                " m and are no contact nodes: a larger 'Contact/Zone " + std::to_string(z + 1) +
                "/Search distance' couples them";
      }
    return text;
  }

  LoadBalance
  ContactState::test_load_balance(const std::vector<std::unique_ptr<Body>> &bodies,
                                  const std::optional<double>               tresca_slip_bound,
                                  const MPI_Comm                            comm)
  {
    // The test of this rank's nodes, those the contact solver will hold (find_contact_nodes()
    // gives a rank the nodes of its home vertices).
    load_balance_test = std::make_unique<LoadBalanceTest>(bodies, found, comm);
    return tresca_slip_bound ?
             load_balance_test->tresca(std::vector<double>(found.size(), *tresca_slip_bound)) :
             load_balance_test->coulomb();
  }

  std::string
  ContactState::no_equilibrium_message(const LoadBalance &balance, const bool tresca) const
  {
    std::ostringstream text;
    text << "no equilibrium: the loads cannot be balanced by contact forces within "
         << (tresca ? "the bounds λ_N ≥ 0, ‖λ_T‖ ≤ g (Tresca)" : "the friction cones ‖λ_T‖ ≤ μ λ_N")
         << ". On the rigid motion with " << balance.motion << " the loads do the work "
         << InputParsing::number_text(balance.load_work) << " J per metre of that motion, and ";
    if (std::isfinite(balance.force_bound))
      text << "only contact forces whose magnitudes sum to more than "
           << InputParsing::number_text(balance.force_bound) << " N (" << std::setprecision(2)
           << balance.force_bound / balance.load_resultant << std::setprecision(6)
           << " times the loads' resultant) could oppose it";
    else
      text << "no contact force within them can oppose it";
    text << ". A body held only by contact is pulled off its obstacle, or its tangential loads "
            "exceed what friction can hold (full sliding)"
         << uncoupled_vertices_text();
    return text.str();
  }

  void
  ContactState::hold(const DualProblem               &dual,
                     const DualLayout                &layout,
                     const std::vector<unsigned int> &owner,
                     const std::vector<unsigned int> &first_subdomain,
                     const MPI_Comm                   comm)
  {
    const unsigned int rank = Utilities::MPI::this_mpi_process(comm);
    dual_rows.emplace(dual);
    held_nodes = hold_contact_nodes(found, layout, [&](const unsigned int k) {
      return owner[first_subdomain[found[k].body] + found[k].copies.parts.front()] == rank;
    });
    // The rows of a node belong to its home subdomain (DualRows::held_by): a rank holds the
    // normal rows of exactly its nodes. Checked by all ranks together, so that all stop.
    std::string  error;
    unsigned int n_normal = 0;
    for_each_held_row(dual_rows->vector(), [&](const unsigned int row, const double) {
      n_normal += row >= layout.first_normal() && row < layout.first_equality();
    });
    for (unsigned int k = 0; k < held_nodes.nodes.size(); ++k)
      if (dual_rows->local_index(held_nodes.layout.normal_row[k]) == numbers::invalid_unsigned_int)
        error = "the rows of contact node " + std::to_string(held_nodes.layout.node_number(k)) +
                " are not held by the rank of its home subdomain";
    if (error.empty() && n_normal != held_nodes.nodes.size())
      error = "rank " + std::to_string(rank) + " holds " + std::to_string(n_normal) +
              " normal rows of contact nodes and " + std::to_string(held_nodes.nodes.size()) +
              " contact nodes";
    error = MPITools::first_error(comm, error);
    AssertThrow(error.empty(), ExcMessage("Contact nodes and their rows: " + error + "."));
  }

  double
  ContactState::multiplier(const DualVector &lambda, const unsigned int row) const
  {
    return lambda.local_element(dual_rows->local_index(row));
  }

  std::vector<std::array<unsigned int, 3>>
  ContactState::vertices_read() const
  {
    std::vector<std::array<unsigned int, 3>> wanted; // (body, vertex, home part)
    for (const auto *list : {&contact_surfaces.slave, &contact_surfaces.master})
      for (const ContactTriangle &t : *list)
        for (unsigned int i = 0; i < 3; ++i)
          wanted.push_back({{t.body, t.vertices[i], t.home[i]}});
    for (const ContactSurfaces::Vertex &v : contact_surfaces.uncoupled)
      wanted.push_back({{v.body, v.vertex, v.home}});
    for (const ContactNode &node : held_nodes.nodes)
      {
        wanted.push_back({{node.body, node.vertex, node.copies.parts.front()}});
        for (const MasterPoint &m : node.master)
          wanted.push_back({{m.body, m.vertex, m.copies.parts.front()}});
      }
    return wanted;
  }

  ContactEvaluation
  ContactState::evaluate(const DualVector           &lambda,
                         const VertexDisplacements  &surface_u,
                         const double                u_max,
                         const double                vertex_penetration,
                         const double                largest_cell,
                         const Parameters::Contact  &contact,
                         const std::optional<double> tresca_slip_bound,
                         const unsigned int          n_bodies,
                         const MPI_Comm              comm) const
  {
    ContactEvaluation evaluation;
    evaluation.results = evaluate_contact(
      held_nodes.nodes,
      held_nodes.layout,
      [&](const unsigned int row) { return multiplier(lambda, row); },
      surface_u,
      u_max,
      evaluation.check,
      tresca_slip_bound,
      comm);
    // The independent check counts every vertex of the bodies in front of a rigid plane too.
    const double on_surface =
      surface_penetration(contact, contact_surfaces, surface_u, u_max, largest_cell, comm);
    evaluation.check.penetration =
      std::max({evaluation.check.penetration,
                on_surface,
                u_max > 0 ? vertex_penetration / u_max : vertex_penetration});
    // Mortar rows hold the gap weakly: the pointwise overlap of their surfaces, reported apart.
    if (std::find(mortar_zones.begin(), mortar_zones.end(), true) != mortar_zones.end())
      evaluation.check.mortar_overlap =
        mortar_overlap(mortar_zones, contact_surfaces, surface_u, u_max, largest_cell, comm);
    evaluation.forces =
      ContactForces::of(held_nodes.nodes, evaluation.results, n_bodies, contact.zones.size(), comm);
    return evaluation;
  }

  std::size_t
  ContactState::memory_consumption() const
  {
    return FetiContact::memory_consumption(found, contact_surfaces) +
           FetiContact::memory_consumption(held_nodes.nodes, ContactSurfaces());
  }
} // namespace FetiContact
