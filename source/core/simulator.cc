#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/grid/grid_tools.h>

#include <feticontact/base/block_partition.h>
#include <feticontact/base/exact_sum.h>
#include <feticontact/base/input_parsing.h>
#include <feticontact/base/mpi_tools.h>
#include <feticontact/base/subdomain_threads.h>
#include <feticontact/contact/contact_results.h>
#include <feticontact/contact/contact_solver.h>
#include <feticontact/contact/load_balance.h>
#include <feticontact/core/simulator.h>
#include <feticontact/feti/local_dual_rows.h>
#include <feticontact/postprocessing/postprocessors.h>
#include <feticontact/postprocessing/stresses.h>
#include <feticontact/postprocessing/verification.h>
#include <feticontact/qp/projected_cg.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <numeric>
#include <utility>

namespace FetiContact
{
  using namespace dealii;


  Simulator::Simulator(const MPI_Comm           comm,
                       const Parameters::Scene &parameters,
                       const std::string       &effective_parameters,
                       const std::string       &input)
    : comm(comm)
    , rank(Utilities::MPI::this_mpi_process(comm))
    , n_ranks(Utilities::MPI::n_mpi_processes(comm))
    , parameters(parameters)
    , effective_parameters(effective_parameters)
    , input(input)
    , output(comm, parameters.output.directory)
    , pcout(output.log(), rank == 0)
    , timer(pcout, TimerOutput::never, TimerOutput::wall_times)
    , fe(FE_SimplexP<3>(1), 3)
    , mapping(FE_SimplexP<3>(1))
  {}

  void
  Simulator::validate()
  {
    set_up_scene();
  }

  void
  Simulator::set_up_scene()
  {
    TimerOutput::Scope scope(timer, "setup");
    estimate_memory();
    set_up_bodies();
    set_up_contact_nodes();
  }

  void
  Simulator::estimate_memory()
  {
    memory_estimate = MemoryEstimate::of(parameters, comm);
    pcout << "Memory: estimated peak "
          << InputParsing::number_text(std::round(memory_estimate.peak_mib)) << " MiB per rank, "
          << InputParsing::number_text(std::round(memory_estimate.available_mib))
          << " MiB per rank available (" << memory_estimate.available_source << ")" << std::endl;
    memory_estimate.check(parameters);
    if (memory_estimate.tight())
      pcout << "Warning: the estimated peak memory exceeds the memory available by less than the "
               "model's error; the system may stop this run (doc/performance.md, \"Memory\")."
            << std::endl;
  }

  void
  Simulator::set_up_bodies()
  {
    // The bodies' cells are distributed: rank 0 creates and partitions every mesh, and every
    // rank keeps the cells of its own subdomains.
    require(n_ranks == 1 || !parameters.output.write_fclib,
            "Output/Write FCLIB problem: the export assembles the undecomposed bodies on rank 0, "
            "and on several ranks no rank holds their whole meshes: run the export on one rank.");
    first_subdomain.clear();
    unsigned int n_subdomains = 0;
    for (unsigned int b = 0; b < parameters.bodies.size(); ++b)
      {
        bodies.push_back(std::make_unique<Body>(parameters.bodies[b], b));
        bodies.back()->create_and_partition(comm);
        first_subdomain.push_back(n_subdomains);
        n_subdomains += bodies.back()->partition.n_parts;
      }
    first_subdomain.push_back(n_subdomains);
    distribute_subdomains();
    for (const auto &body : bodies)
      {
        body->distribute(
          [&](const unsigned int part) { return owner[first_subdomain[body->index] + part]; });
        body->set_up_boundary();
        if (!in_contact(parameters.contact, body->index))
          body->check_held();
        pcout << "Body '" << body->parameters.name << "': " << body->n_cells << " tetrahedra, "
              << body->n_vertices << " vertices, " << body->partition.n_parts << " subdomains"
              << std::endl;
      }
    // Read (and check) reference displacements before any solving, so that a wrong file is
    // refused without output.
    if (!parameters.verification.reference_displacements.empty())
      reference_displacements =
        read_reference_displacements(parameters.verification.reference_displacements, bodies);
  }

  void
  Simulator::set_up_contact_nodes()
  {
    std::vector<ZoneReport> &reports = zone_reports;
    Timer                    search_timer;
    // Every rank finds the nodes of its home vertices, whose rows it will hold.
    contact_nodes =
      find_contact_nodes(bodies, parameters.contact, &contact_surfaces, &reports, true);
    n_contact_nodes = Utilities::MPI::sum(static_cast<unsigned int>(contact_nodes.size()), comm);
    contact_rows_time += search_timer.wall_time();
    mortar_zones.clear();
    for (const ZoneReport &r : reports)
      mortar_zones.push_back(r.discretization == "mortar");
    for (unsigned int z = 0; z < reports.size(); ++z)
      {
        const ZoneReport &r = reports[z];
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
    check_bodies_held_by_contact();
    require(n_contact_nodes > 0 || !parameters.verification.hertz.enabled,
            "Verification/Hertz: the scene has no contact nodes.");
    require(n_contact_nodes > 0 || !parameters.output.write_fclib,
            "Output/Write FCLIB problem: the scene has no contact nodes.");
    for (const auto &node : contact_nodes)
      require(!parameters.output.write_fclib || !node.keeper || node.friction == 0,
              "Output/Write FCLIB problem: the node at " + InputParsing::number_text(node.x[0]) +
                ", " + InputParsing::number_text(node.x[1]) + ", " +
                InputParsing::number_text(node.x[2]) +
                " lies on the surfaces of several zones "
                "with friction, whose friction adds up along their edge; FCLIB's problems have "
                "one friction cone per contact and cannot express it.");
  }

  void
  Simulator::test_load_balance()
  {
    if (n_contact_nodes == 0)
      return;
    TimerOutput::Scope scope(timer, "setup");
    const bool         tresca =
      parameters.contact_solver.friction_law == Parameters::ContactSolver::FrictionLaw::tresca;
    // The test of this rank's nodes, those the contact solver will hold (find_contact_nodes()
    // gives a rank the nodes of its home vertices).
    load_balance_test = std::make_unique<LoadBalanceTest>(bodies, contact_nodes, comm);
    const LoadBalance balance =
      tresca ? load_balance_test->tresca(
                 std::vector<double>(contact_nodes.size(), parameters.contact_solver.slip_bound)) :
               load_balance_test->coulomb();
    const char *outcome[] = {"balanced", "impossible", "undecided"};
    summary.set("load_balance",
                JsonObject()
                  .set("outcome", outcome[static_cast<int>(balance.outcome)])
                  .set("relative_residual", balance.relative_residual)
                  .set("iterations", balance.iterations));
    if (balance.outcome == LoadBalance::Outcome::undecided)
      pcout << "Load balance: undecided after " << balance.iterations
            << " iterations (relative residual " << balance.relative_residual
            << "); the solve decides" << std::endl;
    if (balance.outcome != LoadBalance::Outcome::impossible)
      return;
    message                = no_equilibrium_message(balance, tresca);
    equilibrium_impossible = true;
    converged              = false;
    pcout << "Load balance: " << message << std::endl;
    summary.set("solver_message", message).set("no_equilibrium", true);
  }

  void
  Simulator::check_bodies_held_by_contact() const
  {
    // Contact nodes per body, as slave or as master, over all ranks.
    std::vector<unsigned int> touching(bodies.size());
    for (const ContactNode &node : contact_nodes)
      {
        ++touching[node.body];
        for (const MasterPoint &m : node.master)
          ++touching[m.body];
      }
    MPI_Allreduce(MPI_IN_PLACE, touching.data(), touching.size(), MPI_UNSIGNED, MPI_SUM, comm);
    for (const auto &body : bodies)
      {
        if (touching[body->index] > 0 || !in_contact(parameters.contact, body->index))
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
  Simulator::uncoupled_vertices_text() const
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

  std::string
  Simulator::no_equilibrium_message(const LoadBalance &balance, const bool tresca) const
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

  bool
  Simulator::stop_without_equilibrium()
  {
    summary.set_leading("converged", false)
      .set_leading("n_subdomains", first_subdomain.back())
      .set_leading("n_contact_nodes", n_contact_nodes)
      .set_leading("n_mpi_ranks", n_ranks);
    output.write_summary(summary.str());
    timer.print_summary();
    output.commit();
    return false;
  }

  void
  Simulator::set_up_subdomains()
  {
    TimerOutput::Scope scope(timer, "setup");
    const bool         primal =
      parameters.feti.dirichlet_treatment == Parameters::Feti::DirichletTreatment::primal;
    // The sub-meshes and their DoFs, one subdomain per call on the subdomain threads.
    std::vector<std::pair<const Body *, unsigned int>> parts;
    for (const auto &body : bodies)
      for (unsigned int p = 0; p < body->partition.n_parts; ++p)
        if (owner[first_subdomain[body->index] + p] == rank)
          parts.emplace_back(body.get(), p);
    std::vector<std::vector<std::vector<unsigned int>>> parts_of_vertex(bodies.size());
    for (const auto &[body, p] : parts)
      if (parts_of_vertex[body->index].empty())
        parts_of_vertex[body->index] = body->parts_of_mesh_vertices();
    subdomains.resize(parts.size());
    SubdomainThreads::for_each(parts.size(), [&](const unsigned int i) {
      const auto &[body, p] = parts[i];
      subdomains[i]         = std::make_unique<Subdomain>(*body,
                                                  body->part_cells(p, parts_of_vertex[body->index]),
                                                  first_subdomain[body->index] + p,
                                                  primal,
                                                  fe);
    });
    for (const auto &s : subdomains)
      owned.push_back(s.get());
    build_dual_rows();
  }

  void
  Simulator::distribute_subdomains()
  {
    // Contiguous ranges of subdomains, balanced by their numbers of cells (each rank at most
    // its share plus one subdomain). Blocks are numbered lexicographically, so a range of them
    // is a slab, and the rows of B between two ranks' sets of subdomains, whose terms are
    // exchanged in every multiplication by F (DualProblem), are those of a few planar cuts.
    // (METIS numbers its parts without such a guarantee: there the exchange can be larger.)
    // Every rank computes the same assignment.
    const unsigned int        n = first_subdomain.back();
    std::vector<unsigned int> cells_before(n + 1, 0);
    for (const auto &body : bodies)
      for (unsigned int p = 0; p < body->partition.n_parts; ++p)
        cells_before[first_subdomain[body->index] + p + 1] = body->cells_per_part[p];
    std::partial_sum(cells_before.begin(), cells_before.end(), cells_before.begin());
    const BlockPartition ranges = BlockPartition::balanced(comm, cells_before);
    owner.assign(n, 0);
    for (unsigned int r = 0; r < n_ranks; ++r)
      for (unsigned int s = ranges.firsts()[r]; s < ranges.firsts()[r + 1]; ++s)
        owner[s] = r;
  }

  void
  Simulator::build_dual_rows()
  {
    const bool primal =
      parameters.feti.dirichlet_treatment == Parameters::Feti::DirichletTreatment::primal;
    // λ = [λ_T; λ_N; λ_E]: contact rows first, then gluing and TFETI Dirichlet rows.
    const bool polygonal =
      parameters.contact_solver.algorithm == Parameters::ContactSolver::Algorithm::polygonal;
    // A rank keeps the rows that touch its subdomains: the contact rows of the nodes on them,
    // each node's rows together (its home vertex's rank makes them and sends them to the ranks
    // of the master side), and the equality rows of their vertices, made without any rank
    // holding all.
    const bool     local_rows = n_ranks > 1;
    const unsigned directions = polygonal ? parameters.contact_solver.polygon_directions : 0;
    Timer          rows_timer;
    rows = build_shared_contact_rows(comm,
                                     contact_nodes,
                                     first_subdomain,
                                     owner,
                                     layout,
                                     directions,
                                     parameters.feti.average_contact_rows,
                                     !local_rows);
    contact_rows_time += rows_timer.wall_time();
    const DualRows equality = local_rows ? build_local_equality_rows(comm, owned, owner, !primal) :
                                           build_equality_rows(comm, owned, !primal);
    layout.n_equality       = equality.n_all;
    rows.append(equality);
    if (n_contact_nodes > 0)
      pcout << "Contact: " << n_contact_nodes << " contact nodes, " << layout.n_normal
            << " normal and " << layout.n_tangential << " tangential multipliers" << std::endl;
  }

  void
  Simulator::assemble()
  {
    TimerOutput::Scope scope(timer, "assembly");
    SubdomainThreads::for_each(owned.size(),
                               [&](const unsigned int i) { owned[i]->assemble(mapping); });
  }

  void
  Simulator::factorize()
  {
    factorize_subdomains();
    build_dual_problem();
    hold_contact_nodes_here();
    pcout << "FETI: " << first_subdomain.back() << " subdomains on " << n_ranks << " rank(s) × "
          << SubdomainThreads::n_threads() << " thread(s), " << mode_offset.back()
          << " rigid body modes, " << dual->size() << " dual unknowns" << std::endl;
    output.check_log();
  }

  void
  Simulator::factorize_subdomains()
  {
    TimerOutput::Scope scope(timer, "factorization");
    SubdomainThreads::for_each(
      owned.size(),
      [&](const unsigned int i) { owned[i]->factorize(parameters.feti.local_solver); },
      LocalSolver::create(parameters.feti.local_solver)->thread_safe());
    std::vector<double> n_modes(first_subdomain.back(), 0.0);
    for (auto *s : owned)
      n_modes[s->global_index] = s->R.n();
    Utilities::MPI::sum(make_array_view(std::as_const(n_modes)), comm, make_array_view(n_modes));
    mode_offset.assign(n_modes.size() + 1, 0);
    for (unsigned int s = 0; s < n_modes.size(); ++s)
      mode_offset[s + 1] = mode_offset[s] + static_cast<unsigned int>(n_modes[s]);
  }

  void
  Simulator::build_dual_problem()
  {
    TimerOutput::Scope scope(timer, "coarse problem");
    dual = std::make_unique<DualProblem>(comm,
                                         owned,
                                         mode_offset,
                                         rows,
                                         parameters.feti.coarse_factor ==
                                             Parameters::Feti::CoarseFactor::per_rank ?
                                           CoarseProblem::FactorStorage::per_rank :
                                           CoarseProblem::FactorStorage::per_node);
  }

  void
  Simulator::solve()
  {
    if (n_contact_nodes == 0)
      solve_linear();
    else
      solve_contact();
    output.check_log();
    solve_F_time                      = dual->F_time;
    solve_F_local_time                = dual->F_local_time;
    solve_F_applications              = dual->n_F_applications;
    solve_preconditioner_time         = dual->lumped_time;
    solve_preconditioner_applications = dual->n_lumped_applications;
  }

  void
  Simulator::solve_linear()
  {
    TimerOutput::Scope  scope(timer, "solve");
    const LocalDualRows rows(*dual);
    DualVector          solution = rows.vector();
    dual->coarse.least_norm_solution(dual->e, solution);
    const auto report =
      QP::ProjectedCG<DualVector>(parameters.feti.projected_cg)
        .solve([this](const DualVector &x, DualVector &y) { dual->apply_F(x, y); },
               [this](DualVector &x) { dual->coarse.project(x); },
               rows.h(),
               solution,
               [this](unsigned int it, double residual) {
                 if (it % 50 == 0)
                   pcout << "  PCG iteration " << std::setw(5) << it
                         << "   ‖P(Fλ − h)‖ / ‖Ph‖ = " << std::scientific << std::setprecision(3)
                         << residual << std::defaultfloat << std::endl;
               },
               parameters.feti.lumped_preconditioner ?
                 QP::Operator<DualVector>(
                   [this](const DualVector &x, DualVector &y) { dual->apply_lumped(x, y); }) :
                 QP::Operator<DualVector>());
    const double drift = dual->coarse.restore_feasibility(solution, dual->e);
    lambda             = std::move(solution);
    summary.set("coarse_residual_before_restoration", drift);
    converged  = report.converged;
    iterations = report.iterations;
    pcout << "Projected CG: " << (converged ? "converged" : "NOT converged") << " after "
          << report.iterations << " iterations, relative projected gradient " << std::scientific
          << std::setprecision(3) << report.relative_residual << std::defaultfloat << std::endl;
    summary.set("pcg_relative_residual", report.relative_residual);
    message = projected_cg_message(report);
    summary.set("solver_message", message);
  }

  std::string
  Simulator::projected_cg_message(const QP::SolverReport &report) const
  {
    const double tolerance = parameters.feti.projected_cg.tolerance;
    if (report.converged)
      return "converged";
    if (report.stagnated)
      return "projected CG stagnated after " + std::to_string(report.iterations) +
             " iterations at the relative projected gradient " +
             InputParsing::number_text(report.relative_residual) + " (recomputed from λ), above " +
             "FETI/Relative tolerance = " + InputParsing::number_text(tolerance) +
             ": its least value did not halve over the last quarter of the iterations, so the "
             "rounding of F = B K⁺ Bᵀ bounds the attainable accuracy (ill-conditioned subdomain "
             "matrices, e.g. a thin plate); a tolerance at or above that value is attainable";
    return "projected CG did not converge in FETI/Maximum iterations = " +
           std::to_string(parameters.feti.projected_cg.max_iterations) +
           " iterations (relative projected gradient " +
           InputParsing::number_text(report.relative_residual) + ", tolerance " +
           InputParsing::number_text(tolerance) + ")";
  }

  void
  Simulator::solve_contact()
  {
    TimerOutput::Scope scope(timer, "solve");
    // The solver works on the nodes whose rows this rank holds.
    const HeldContactNodes &held = held_contact;
    ContactSolver           solver(
      *dual, held.layout, held.nodes, parameters.contact_solver, pcout.get_stream());
    if (load_balance_test && load_balance_test->has_free_motions())
      solver.set_equilibrium_test(
        [this](const std::vector<double> &g) { return load_balance_test->tresca(g); });
    const auto result = solver.solve();
    // The iteration history, also when the solver proved that no equilibrium exists.
    output.on_all_ranks([&]() {
      if (rank == 0)
        ContactSolver::write_history(result.history,
                                     output.results().open(parameters.output.directory +
                                                           "/history.csv"));
    });
    lambda = result.lambda;
    // Primal recovery: Fλ − h + Gᵀμ is the gradient of the Lagrangian, and
    // Fλ − h = −(Bu − c) + Gᵀα, so α = −μ makes Bu − c the negative of that gradient: zero on
    // the equality rows and the gaps on the contact rows.
    alpha = result.mu;
    alpha *= -1.0;
    alpha_given = true;
    converged   = result.converged;
    iterations  = result.outer_iterations;
    n_bound     = result.n_bound;
    n_disc      = result.n_disc;
    pcout << "Contact solver: " << result.message << "; outer iterations "
          << result.outer_iterations << ", SMALBE iterations " << result.smalbe_iterations
          << ", Hessian multiplications " << result.n_bound << " (bound QP) + " << result.n_disc
          << " (disc QP)" << std::endl;
    summary.set("solver_message", result.message);
    summary.set("no_equilibrium", result.no_equilibrium);
    message                = result.message;
    equilibrium_impossible = result.no_equilibrium;
    summary.set("smalbe_iterations", result.smalbe_iterations);
    summary.set("mpgp_steps",
                JsonObject()
                  .set("cg", result.cg_steps)
                  .set("expansion", result.expansion_steps)
                  .set("proportioning", result.proportioning_steps)
                  .set("expansion_fallbacks", result.expansion_fallbacks)
                  .set("recursive_gradient_updates", result.recursive_gradient_updates));
  }

  void
  Simulator::postprocess()
  {
    // Without equilibrium the multipliers are not a solution: no displacement or contact files.
    if (equilibrium_impossible)
      return;
    recover_primal();
    TimerOutput::Scope          scope(timer, "output");
    const Evaluation            evaluation = evaluate_solution();
    const Postprocessing::Input input{comm,
                                      parameters,
                                      bodies,
                                      first_subdomain,
                                      owner,
                                      owned,
                                      u,
                                      evaluation.lambda_not_finite,
                                      evaluation.u_not_finite,
                                      evaluation.u_max,
                                      evaluation.interface_jump,
                                      evaluation.largest_strain,
                                      held_contact.nodes,
                                      held_contact.layout,
                                      contact_surfaces,
                                      evaluation.contact_results,
                                      evaluation.contact_check,
                                      evaluation.contact_forces,
                                      reference_displacements,
                                      mapping,
                                      fe,
                                      parameters.output.directory,
                                      output.results(),
                                      summary,
                                      pcout};
    summary.set_solver_converged(converged);
    for (const auto &postprocessor : Postprocessing::create(parameters, n_contact_nodes > 0))
      {
        postprocessor->execute(input);
        if (const auto *hertz =
              dynamic_cast<const Postprocessing::HertzComparison *>(postprocessor.get()))
          run_statistics.hertz = hertz->result();
      }
    if (!summary.check_failure().empty())
      {
        converged = false;
        message   = summary.check_failure();
      }
  }

  void
  Simulator::recover_primal()
  {
    TimerOutput::Scope scope(timer, "primal recovery");
    u = alpha_given ? dual->recover_primal(lambda, alpha) : dual->recover_primal(lambda);
  }

  void
  Simulator::hold_contact_nodes_here()
  {
    dual_rows.emplace(*dual);
    held_contact = hold_contact_nodes(contact_nodes, layout, [this](const unsigned int k) {
      return holds_contact_node(contact_nodes[k]);
    });
    // The rows of a node belong to its home subdomain (DualRows::held_by): a rank holds the
    // normal rows of exactly its nodes. Checked by all ranks together, so that all stop.
    std::string      error;
    const DualVector row_numbers = dual_rows->vector();
    unsigned int     n_normal    = 0;
    for (unsigned int i = 0; i < row_numbers.locally_owned_size(); ++i)
      n_normal += row_numbers.global_index(i) >= layout.first_normal() &&
                  row_numbers.global_index(i) < layout.first_equality();
    for (unsigned int k = 0; k < held_contact.nodes.size(); ++k)
      if (dual_rows->local_index(held_contact.layout.normal_row[k]) ==
          numbers::invalid_unsigned_int)
        error = "the rows of contact node " + std::to_string(held_contact.layout.node_number(k)) +
                " are not held by the rank of its home subdomain";
    if (error.empty() && n_normal != held_contact.nodes.size())
      error = "rank " + std::to_string(rank) + " holds " + std::to_string(n_normal) +
              " normal rows of contact nodes and " + std::to_string(held_contact.nodes.size()) +
              " contact nodes";
    error = MPITools::first_error(comm, error);
    AssertThrow(error.empty(), ExcMessage("Contact nodes and their rows: " + error + "."));
  }

  bool
  Simulator::holds_contact_node(const ContactNode &node) const
  {
    return owner[first_subdomain[node.body] + node.copies.parts.front()] == rank;
  }

  double
  Simulator::contact_multiplier(const unsigned int row) const
  {
    return lambda[dual_rows->local_index(row)];
  }

  unsigned int
  Simulator::multipliers_not_finite() const
  {
    unsigned int n = 0;
    for (const double l : lambda)
      n += !std::isfinite(l);
    return Utilities::MPI::sum(n, comm);
  }

  double
  Simulator::largest_equality_residual() const
  {
    double           jump     = 0;
    const DualVector residual = dual->constraint_residual(u);
    for (unsigned int i = 0; i < residual.locally_owned_size(); ++i)
      if (residual.global_index(i) >= layout.first_equality())
        jump = std::max(jump, std::abs(residual[i]));
    return Utilities::MPI::max(jump, comm);
  }

  Simulator::Evaluation
  Simulator::evaluate_solution() const
  {
    Evaluation evaluation;
    // Every vertex once, in the subdomain that reports it.
    for (unsigned int i = 0; i < owned.size(); ++i)
      for (const auto &[w, v] : owned[i]->reported_vertices())
        {
          Tensor<1, 3> u_v;
          for (unsigned int c = 0; c < 3; ++c)
            {
              u_v[c] = u[i][owned[i]->vertex_dofs[v][c]];
              evaluation.u_not_finite += !std::isfinite(u_v[c]);
            }
          evaluation.u_max = std::max(evaluation.u_max, u_v.norm());
          if (n_contact_nodes > 0)
            evaluation.vertex_penetration =
              std::max(evaluation.vertex_penetration,
                       vertex_penetration(parameters.contact,
                                          owned[i]->body.index,
                                          owned[i]->mesh.get_vertices()[v],
                                          u_v));
        }
    evaluation.u_max              = Utilities::MPI::max(evaluation.u_max, comm);
    evaluation.u_not_finite       = Utilities::MPI::sum(evaluation.u_not_finite, comm);
    evaluation.vertex_penetration = Utilities::MPI::max(evaluation.vertex_penetration, comm);
    // Constraint residual B_E u − c: the jump of the displacements across interfaces (and the
    // Dirichlet misfit in TFETI), relative to the largest displacement. Only the equality rows:
    // the contact rows of B u − c are the gaps and the slips.
    const double jump            = largest_equality_residual();
    evaluation.lambda_not_finite = multipliers_not_finite();
    evaluation.interface_jump    = evaluation.u_max > 0 ? jump / evaluation.u_max : jump;
    if (evaluation.u_not_finite == 0)
      for (unsigned int i = 0; i < owned.size(); ++i)
        for (const auto &strain : cell_strains(*owned[i], mapping, u[i]))
          for (const double e : eigenvalues(strain))
            evaluation.largest_strain = std::max(evaluation.largest_strain, std::abs(e));
    evaluation.largest_strain = Utilities::MPI::max(evaluation.largest_strain, comm);
    evaluation.contact_forces.on_body.resize(bodies.size());
    evaluation.contact_forces.of_zone.resize(parameters.contact.zones.size());
    if (n_contact_nodes > 0)
      evaluate_contact(evaluation);
    return evaluation;
  }

  void
  Simulator::evaluate_contact(Evaluation &evaluation) const
  {
    const bool tresca =
      parameters.contact_solver.friction_law == Parameters::ContactSolver::FrictionLaw::tresca;
    evaluation.surface_u       = contact_displacements();
    evaluation.contact_results = FetiContact::evaluate_contact(
      held_contact.nodes,
      held_contact.layout,
      [this](const unsigned int row) { return contact_multiplier(row); },
      evaluation.surface_u,
      evaluation.u_max,
      evaluation.contact_check,
      tresca ? std::optional<double>(parameters.contact_solver.slip_bound) : std::nullopt,
      comm);
    // The independent check counts every vertex of the bodies in front of a rigid plane too.
    double largest_cell = 0;
    for (const Subdomain *s : owned)
      largest_cell = std::max(largest_cell, GridTools::maximal_cell_diameter(s->mesh));
    largest_cell            = Utilities::MPI::max(largest_cell, comm);
    const double u_max      = evaluation.u_max;
    const double on_surface = surface_penetration(
      parameters.contact, contact_surfaces, evaluation.surface_u, u_max, largest_cell, comm);
    evaluation.contact_check.penetration =
      std::max({evaluation.contact_check.penetration,
                on_surface,
                u_max > 0 ? evaluation.vertex_penetration / u_max : evaluation.vertex_penetration});
    // Mortar rows hold the gap weakly: the pointwise overlap of their surfaces, reported apart.
    if (std::find(mortar_zones.begin(), mortar_zones.end(), true) != mortar_zones.end())
      evaluation.contact_check.mortar_overlap = mortar_overlap(
        mortar_zones, contact_surfaces, evaluation.surface_u, u_max, largest_cell, comm);
    evaluation.contact_forces = ContactForces::of(held_contact.nodes,
                                                  evaluation.contact_results,
                                                  bodies.size(),
                                                  parameters.contact.zones.size(),
                                                  comm);
  }

  VertexDisplacements
  Simulator::contact_displacements() const
  {
    std::vector<std::array<unsigned int, 3>> wanted; // (body, vertex, home part)
    for (const auto *list : {&contact_surfaces.slave, &contact_surfaces.master})
      for (const ContactTriangle &t : *list)
        for (unsigned int i = 0; i < 3; ++i)
          wanted.push_back({{t.body, t.vertices[i], t.home[i]}});
    for (const ContactSurfaces::Vertex &v : contact_surfaces.uncoupled)
      wanted.push_back({{v.body, v.vertex, v.home}});
    for (const ContactNode &node : held_contact.nodes)
      {
        wanted.push_back({{node.body, node.vertex, node.copies.parts.front()}});
        for (const MasterPoint &m : node.master)
          wanted.push_back({{m.body, m.vertex, m.copies.parts.front()}});
      }
    return fetch_vertex_displacements(comm, first_subdomain, owner, owned, u, wanted);
  }

  bool
  Simulator::finish()
  {
    summarize_run();
    output.write_summary(summary.str());
    timer.print_summary();
    output.commit();
    return converged;
  }

  JsonObject
  Simulator::summarize_times(double &total) const
  {
    const auto times = timer.get_summary_data(TimerOutput::total_wall_time);
    const auto time  = [&](const std::string &name) {
      const auto it = times.find(name);
      return it == times.end() ? 0.0 : it->second;
    };
    JsonObject t;
    t.set("setup", time("setup"))
      .set("assembly", time("assembly"))
      .set("factorization", time("factorization"))
      .set("coarse_problem", time("coarse problem"))
      .set("solve", time("solve"))
      .set("primal_recovery", time("primal recovery"))
      .set("output", time("output"))
      .set("contact_rows", Utilities::MPI::max(contact_rows_time, comm));
    total = 0;
    for (const auto &[name, value] : times)
      total += value;
    t.set("total", total);
    // Inside the solve: the applications of F (local solves with the factors, B, Bᵀ, the sum over
    // ranks; the slowest rank) and the rest, the QP's own work (vector operations, projections,
    // the coarse problem's applications of G). The cost floor of the method is the
    // factorization and n_A applications of F; total_over_floor compares the run without output
    // with it.
    const double       hessian_time = Utilities::MPI::max(solve_F_time, comm);
    const double       mean_F = solve_F_applications > 0 ? hessian_time / solve_F_applications : 0;
    const unsigned int n_A    = n_contact_nodes == 0 ? dual->n_F_applications : n_bound + n_disc;
    const double       floor  = time("factorization") + n_A * mean_F;
    // Of the applications of F, the work in the subdomains of the slowest and of the fastest
    // rank; the rest of hessian_applications is the exchange of B u among the ranks and waiting.
    const double local_slowest = Utilities::MPI::max(solve_F_local_time, comm);
    const double local_fastest = Utilities::MPI::min(solve_F_local_time, comm);
    // The lumped preconditioner (zero when off), the slowest rank.
    const double preconditioner_time = Utilities::MPI::max(solve_preconditioner_time, comm);
    const double bookkeeping         = time("solve") - hessian_time - preconditioner_time;
    const double over_floor          = floor > 0 ? (total - time("output")) / floor : 0.0;
    t.set("hessian_applications", hessian_time)
      .set("hessian_local_slowest_rank", local_slowest)
      .set("hessian_local_fastest_rank", local_fastest)
      .set("preconditioner", preconditioner_time)
      .set("preconditioner_applications", solve_preconditioner_applications)
      .set("qp_bookkeeping", bookkeeping)
      .set("one_hessian_application", mean_F)
      .set("cost_floor", floor)
      .set("total_over_floor", over_floor);
    // (A stream of its own: the precision of the solver's lines must not carry over.)
    std::ostringstream line;
    line << std::setprecision(4) << "Time: solve " << time("solve") << " s = applications of F "
         << hessian_time << " s (" << solve_F_applications << ", " << mean_F
         << " s each; local work " << local_slowest << " s on the slowest rank, " << local_fastest
         << " s on the fastest)";
    if (solve_preconditioner_applications > 0)
      line << " + preconditioner " << preconditioner_time << " s ("
           << solve_preconditioner_applications << ")";
    line << " + QP bookkeeping " << bookkeeping
         << " s; cost floor (factorization + n_A × one application of F) " << floor
         << " s, run without output / floor " << over_floor;
    pcout << line.str() << std::endl;
    return t;
  }

  double
  Simulator::meshes_mib() const
  {
    std::size_t bytes = 0;
    for (const auto &body : bodies)
      bytes += body->mesh.memory_consumption();
    return static_cast<double>(bytes) / (1024.0 * 1024.0);
  }

  JsonObject
  Simulator::summarize_memory() const
  {
    // Peak resident memory of every rank (the process's high-water mark: meshes, subdomain
    // matrices and factors, dual vectors, the coarse factor, the MPI library; the
    // pages of the coarse factor shared by a node's ranks count on every rank that reads them).
    Utilities::System::MemoryStats stats;
    Utilities::System::get_memory_stats(stats);
    const std::vector<double> peak_mib =
      Utilities::MPI::all_gather(comm, static_cast<double>(stats.VmHWM) / 1024.0);
    JsonObject memory;
    memory.set("peak_rss_mib_max", *std::max_element(peak_mib.begin(), peak_mib.end()))
      .set("peak_rss_mib_per_rank", peak_mib)
      .set("estimated_peak_mib", memory_estimate.peak_mib)
      .set("model_cells", memory_estimate.cells)
      .set("model_factor_units", memory_estimate.factor_units)
      .set("meshes_mib", meshes_mib())
      .set("contact_mib",
           static_cast<double>(memory_consumption(contact_nodes, contact_surfaces) +
                               memory_consumption(held_contact.nodes, ContactSurfaces())) /
             (1024.0 * 1024.0))
      .set("coarse_shared_mib_per_rank",
           Utilities::MPI::all_gather(comm,
                                      static_cast<double>(dual->coarse.shared_factor_bytes()) /
                                        (1024.0 * 1024.0)));
    pcout << "Peak resident memory per rank: ";
    for (const double p : peak_mib)
      pcout << std::fixed << std::setprecision(0) << p << " MiB " << std::defaultfloat;
    pcout << std::endl;
    return memory;
  }

  JsonObject
  Simulator::summarize_communication() const
  {
    const DualProblem::CommunicationVolume v        = dual->communication_volume();
    const auto                             per_rank = [this](const std::size_t x) {
      return Utilities::MPI::all_gather(comm, static_cast<double>(x));
    };
    return JsonObject()
      .set("slot_neighbours_per_rank", per_rank(v.slot_neighbours))
      .set("slots_sent_per_rank", per_rank(v.slots_sent))
      .set("slots_received_per_rank", per_rank(v.slots_received))
      .set("ghost_neighbours_per_rank", per_rank(v.ghost_neighbours))
      .set("ghosts_received_per_rank", per_rank(v.ghosts_received));
  }

  JsonObject
  Simulator::summarize_local_work() const
  {
    // The subdomain solves each rank made in the multiplications by F.
    return JsonObject().set(
      "subdomain_solves_per_rank",
      Utilities::MPI::all_gather(comm, static_cast<double>(dual->n_subdomain_solves)));
  }

  void
  Simulator::summarize_run()
  {
    unsigned int n_primal = 0, n_primal_feti = 0;
    for (const auto &body : bodies)
      n_primal += body->n_free_dofs();
    for (auto *s : owned)
      n_primal_feti += s->n_unknowns();
    n_primal_feti = Utilities::MPI::sum(n_primal_feti, comm);
    double h_min  = std::numeric_limits<double>::max();
    for (const auto &body : bodies)
      if (body->mesh.n_active_cells() > 0)
        h_min = std::min(h_min, GridTools::minimal_cell_diameter(body->mesh));
    h_min                            = Utilities::MPI::min(h_min, comm);
    const unsigned int n_bound_total = n_contact_nodes == 0 ? dual->n_F_applications : n_bound;
    const unsigned int n_A = n_contact_nodes == 0 ? dual->n_F_applications : n_bound + n_disc;

    double           total_time    = 0;
    const JsonObject times         = summarize_times(total_time);
    const JsonObject memory        = summarize_memory();
    const JsonObject communication = summarize_communication();
    const JsonObject local_work    = summarize_local_work();
    summary.set_leading("converged", converged)
      .set_leading("n_primal", n_primal)
      .set_leading("n_primal_feti", n_primal_feti)
      .set_leading("n_subdomains", first_subdomain.back())
      .set_leading("n_rigid_modes", mode_offset.back())
      .set_leading("h_min", h_min)
      .set_leading("m_total", dual->size())
      .set_leading("m_equality", layout.n_equality)
      .set_leading("m_contact", layout.n_normal + layout.n_tangential)
      .set_leading("iterations", iterations)
      .set_leading("outer_iterations", iterations)
      .set_leading("hessian_multiplications",
                   JsonObject()
                     .set("bound", n_bound_total)
                     .set("disc", n_disc)
                     .set("total", n_A)
                     .set("F_applications", dual->n_F_applications))
      .set_leading("n_mpi_ranks", n_ranks)
      .set_leading("threads_per_rank", SubdomainThreads::n_threads())
      .set_leading("dirichlet_treatment",
                   parameters.feti.dirichlet_treatment ==
                       Parameters::Feti::DirichletTreatment::primal ?
                     "primal" :
                     "total")
      .set_leading("local_solver", parameters.feti.local_solver)
      .set_leading("local_work", local_work)
      .set_leading("times", times)
      .set_leading("memory", memory)
      .set_leading("communication", communication);

    const auto timer_data                  = timer.get_summary_data(TimerOutput::total_wall_time);
    const auto solve_time                  = timer_data.find("solve");
    const auto output_time                 = timer_data.find("output");
    run_statistics.n_primal                = n_primal;
    run_statistics.n_contact_nodes         = n_contact_nodes;
    run_statistics.outer_iterations        = iterations;
    run_statistics.hessian_multiplications = n_A;
    run_statistics.h_min                   = h_min;
    run_statistics.solve_time = solve_time == timer_data.end() ? 0.0 : solve_time->second;
    run_statistics.time_without_output =
      total_time - (output_time == timer_data.end() ? 0.0 : output_time->second);
  }

  bool
  Simulator::run()
  {
    // Rank 0 writes the log. The contact solver prints to the tee directly (not through pcout),
    // so the other ranks' tee must have no destination, or every iteration line would appear
    // once per rank on the terminal.
    if (rank == 0)
      output.log().add(std::cout);
    output.prepare(effective_parameters, input);
    set_up_scene();
    test_load_balance();
    if (equilibrium_impossible)
      return stop_without_equilibrium();
    set_up_subdomains();
    assemble();
    factorize();
    solve();
    postprocess();
    return finish();
  }
} // namespace FetiContact
