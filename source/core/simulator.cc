#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/fe/fe_simplex_p.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/base/subdomain_threads.h>
#include <feticontact/contact/contact_solver.h>
#include <feticontact/core/linear_dual_solution.h>
#include <feticontact/core/simulator.h>
#include <feticontact/core/solution_evaluation.h>
#include <feticontact/postprocessing/postprocessors.h>
#include <feticontact/postprocessing/verification.h>
#include <feticontact/subdomain/subdomain_distribution.h>

#include <cmath>
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
    owner = SubdomainDistribution::owners(bodies, first_subdomain, comm);
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
    work.contact_rows_time += search_timer.wall_time();
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
    RunSummary::set_load_balance(summary, balance);
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
    RunSummary::set_stopped_members(summary, first_subdomain.back(), contact.n_nodes(), n_ranks);
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
    subdomains =
      SubdomainDistribution::make_subdomains(bodies, first_subdomain, owner, rank, primal, fe);
    for (const auto &s : subdomains)
      owned.push_back(s.get());
    build_dual_rows();
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
    work.contact_rows_time += rows_timer.wall_time();
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
    mode_offset = SubdomainDistribution::mode_offsets(owned, first_subdomain.back(), comm);
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
    work.record_applications(*dual);
  }

  void
  Simulator::solve_linear()
  {
    TimerOutput::Scope scope(timer, "solve");
    LinearDualSolution solution = LinearDualSolution::solve(*dual, parameters.feti, pcout);
    lambda                      = std::move(solution.lambda);
    summary.set("coarse_residual_before_restoration", solution.coarse_residual_before_restoration);
    converged       = solution.report.converged;
    work.iterations = solution.report.iterations;
    summary.set("pcg_relative_residual", solution.report.relative_residual);
    message = solution.message;
    summary.set("solver_message", message);
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
    alpha_given     = true;
    converged       = result.converged;
    work.iterations = result.outer_iterations;
    work.n_bound    = result.n_bound;
    work.n_disc     = result.n_disc;
    pcout << "Contact solver: " << result.message << "; outer iterations "
          << result.outer_iterations << ", SMALBE iterations " << result.smalbe_iterations
          << ", Hessian multiplications " << result.n_bound << " (bound QP) + " << result.n_disc
          << " (disc QP)" << std::endl;
    message                = result.message;
    equilibrium_impossible = result.no_equilibrium;
    RunSummary::set_contact_solver(summary, result);
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
    RunSummary::set_leading_members(summary,
                                    {comm,
                                     parameters,
                                     timer,
                                     bodies,
                                     owned,
                                     first_subdomain,
                                     mode_offset,
                                     *dual,
                                     layout,
                                     contact,
                                     memory_estimate,
                                     work,
                                     converged},
                                    pcout,
                                    run_statistics);
    output.write_summary(summary.str());
    timer.print_summary();
    output.commit();
    return converged;
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
