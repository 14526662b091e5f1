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
#include <feticontact/core/solution_evaluation.h>
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
    Timer search_timer;
    contact.find(bodies, parameters.contact, comm);
    contact_rows_time += search_timer.wall_time();
    contact.report_zones(pcout);
    contact.check_bodies_held(bodies, parameters.contact, comm);
    require(contact.n_nodes() > 0 || !parameters.verification.hertz.enabled,
            "Verification/Hertz: the scene has no contact nodes.");
    require(contact.n_nodes() > 0 || !parameters.output.write_fclib,
            "Output/Write FCLIB problem: the scene has no contact nodes.");
    for (const auto &node : contact.nodes())
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
    if (contact.n_nodes() == 0)
      return;
    TimerOutput::Scope scope(timer, "setup");
    const bool         tresca =
      parameters.contact_solver.friction_law == Parameters::ContactSolver::FrictionLaw::tresca;
    const LoadBalance balance =
      contact.test_load_balance(bodies,
                                tresca ?
                                  std::optional<double>(parameters.contact_solver.slip_bound) :
                                  std::nullopt,
                                comm);
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
    message                = contact.no_equilibrium_message(balance, tresca);
    equilibrium_impossible = true;
    converged              = false;
    pcout << "Load balance: " << message << std::endl;
    summary.set("solver_message", message).set("no_equilibrium", true);
  }

  bool
  Simulator::stop_without_equilibrium()
  {
    summary.set_leading("converged", false)
      .set_leading("n_subdomains", first_subdomain.back())
      .set_leading("n_contact_nodes", contact.n_nodes())
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
                                     contact.nodes(),
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
    if (contact.n_nodes() > 0)
      pcout << "Contact: " << contact.n_nodes() << " contact nodes, " << layout.n_normal
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
    contact.hold(*dual, layout, owner, first_subdomain, comm);
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
    if (contact.n_nodes() == 0)
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
    const HeldContactNodes &held = contact.held();
    ContactSolver           solver(
      *dual, held.layout, held.nodes, parameters.contact_solver, pcout.get_stream());
    if (contact.load_balance() && contact.load_balance()->has_free_motions())
      solver.set_equilibrium_test(
        [this](const std::vector<double> &g) { return contact.load_balance()->tresca(g); });
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
    TimerOutput::Scope       scope(timer, "output");
    const SolutionEvaluation evaluation = SolutionEvaluation::of(
      comm, parameters, owned, u, mapping, *dual, layout, lambda, contact, first_subdomain, owner);
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
                                      contact.held().nodes,
                                      contact.held().layout,
                                      contact.surfaces(),
                                      evaluation.contact.results,
                                      evaluation.contact.check,
                                      evaluation.contact.forces,
                                      reference_displacements,
                                      mapping,
                                      fe,
                                      parameters.output.directory,
                                      output.results(),
                                      summary,
                                      pcout};
    summary.set_solver_converged(converged);
    for (const auto &postprocessor : Postprocessing::create(parameters, contact.n_nodes() > 0))
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
    const unsigned int n_A    = contact.n_nodes() == 0 ? dual->n_F_applications : n_bound + n_disc;
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
      .set("contact_mib", static_cast<double>(contact.memory_consumption()) / (1024.0 * 1024.0))
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
    const unsigned int n_bound_total = contact.n_nodes() == 0 ? dual->n_F_applications : n_bound;
    const unsigned int n_A = contact.n_nodes() == 0 ? dual->n_F_applications : n_bound + n_disc;

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
    run_statistics.n_contact_nodes         = contact.n_nodes();
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
