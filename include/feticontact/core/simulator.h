#pragma once

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/lac/vector.h>

#include <feticontact/base/output_directory.h>
#include <feticontact/contact/contact_state.h>
#include <feticontact/core/memory_estimate.h>
#include <feticontact/core/run_summary.h>
#include <feticontact/core/summary.h>
#include <feticontact/feti/dual_problem.h>
#include <feticontact/postprocessing/hertz_comparison.h>
#include <feticontact/postprocessing/interface.h>
#include <feticontact/scene/body.h>
#include <feticontact/scene/scene_parameters.h>
#include <feticontact/subdomain/subdomain.h>

#include <memory>
#include <mpi.h>
#include <optional>
#include <vector>

namespace FetiContact
{
  /**
   * A run of the program on one parameter file, in phases (run()): the set-up of the scene (the
   * memory estimate, the bodies, the contact nodes, the load-balance test), the subdomains (this
   * rank's share) and their assembly, the factorization with the coarse problem, the solve, and
   * the postprocessing: the primal recovery, then the postprocessors the parameter file selects
   * (Postprocessing::create()). The phases and the postprocessors fill the Summary, written once
   * at the end with the other result files (log.txt, summary.json, ParaView files). Phases are
   * timed with TimerOutput.
   */
  class Simulator
  {
  public:
    /**
     * @p effective_parameters and @p input are written into the output directory
     * (parameters.prm and input.prm).
     */
    Simulator(const MPI_Comm           comm,
              const Parameters::Scene &parameters,
              const std::string       &effective_parameters,
              const std::string       &input);

    /**
     * Runs everything; returns true if the dual solver converged. Throws InputError for a scene
     * that cannot be solved as posed and OutputError for a result file that cannot be written
     * (then no result file is left; result files are written under temporary names and renamed
     * when the run has written all of them, summary.json last).
     */
    bool
    run();

    /**
     * --validate: the set-up of run() (the memory estimate, the bodies and the checks that they
     * are held, the reference displacements, the contact nodes and what the output asks of
     * them) without creating the output directory or writing any file or log line. Throws
     * InputError as run() would.
     */
    void
    validate();

    /**
     * The contact solver's closing message ("converged", or why it stopped). When it proved
     * that no equilibrium exists (no_equilibrium(), before the solve by the load-balance test
     * or in it by SMALBE's certificate), run() writes no result files, only log.txt, summary.json
     * with "converged": false and (after a solve) history.csv.
     */
    const std::string &
    solver_message() const
    {
      return message;
    }
    bool
    no_equilibrium() const
    {
      return equilibrium_impossible;
    }

    /** What a refinement study tabulates of a run (RefinementStudy). */
    using Statistics = RunStatistics;
    /** Available after run(). */
    const Statistics &
    statistics() const
    {
      return run_statistics;
    }

  private:
    /**
     * The set-up of the scene: the memory estimate, the bodies (and that each is held), the
     * reference displacements, the contact nodes (set_up_contact_nodes()).
     */
    void
    set_up_scene();
    /** The memory estimate of the run's peak, checked before any mesh is built. */
    void
    estimate_memory();
    void
    set_up_bodies();
    /** The contact nodes of every zone, and what Verification/Hertz and FCLIB ask of them. */
    void
    set_up_contact_nodes();
    /**
     * The test that contact forces within the friction law's sets can balance the loads on the
     * free rigid motions (LoadBalanceTest): a proof of the contrary sets no_equilibrium() before
     * any subdomain is built.
     */
    void
    test_load_balance();
    /** Writes the summary of a run that stops without equilibrium before the solve. */
    bool
    stop_without_equilibrium();
    /** This rank's subdomains, their meshes and DoFs, and the rows of B. */
    void
    set_up_subdomains();
    /**
     * The rows of B, λ = [λ_T; λ_N; λ_E]: all of them, or with distributed dual vectors on
     * several ranks (and no shared local work) those that touch this rank's subdomains.
     */
    void
    build_dual_rows();
    void
    assemble();
    /** The local factors and the coarse problem (the dual problem). */
    void
    factorize();
    void
    factorize_subdomains();
    void
    build_dual_problem();
    void
    solve();
    /** Projected CG (no contact): LinearDualSolution. */
    void
    solve_linear();
    /** ContactSolver. */
    void
    solve_contact();
    /** The primal recovery, the evaluation of the solution and the postprocessors. */
    void
    postprocess();
    void
    recover_primal();
    /** Writes summary.json, prints the timer table and commits the result files. */
    bool
    finish();

    MPI_Comm           comm;
    const unsigned int rank;
    const unsigned int n_ranks;
    Parameters::Scene  parameters;
    MemoryEstimate     memory_estimate; ///< of the run's peak, made before any mesh is built
    const std::string  effective_parameters, input;
    /** The output directory, its log and this rank's result files. */
    OutputDirectory            output;
    dealii::ConditionalOStream pcout;
    dealii::TimerOutput        timer;

    const dealii::FESystem<3>  fe;
    const dealii::MappingFE<3> mapping;

    std::vector<std::unique_ptr<Body>> bodies;
    std::vector<unsigned int>          first_subdomain; ///< per body, + total at the end
    /** Verification/Reference displacements, by body and vertex (empty: none). */
    std::optional<VertexDisplacements>      reference_displacements;
    std::vector<unsigned int>               owner;      ///< rank of each subdomain
    std::vector<std::unique_ptr<Subdomain>> subdomains; ///< this rank's
    std::vector<Subdomain *>                owned;
    std::vector<unsigned int>               mode_offset;
    /** The rows of B that this rank holds (build_dual_rows()). */
    DualRows rows;
    /** The contact nodes, those whose rows this rank holds, and their evaluation. */
    ContactState contact;
    /** The layout of λ = [λ_T; λ_N; λ_E]: the numbers of its rows of each kind. */
    DualLayout                   layout;
    std::unique_ptr<DualProblem> dual;

    /** The solution λ on this rank's rows. */
    DualVector lambda;
    /** Coefficients of the rigid modes in the primal recovery (contact: from the solver). */
    dealii::Vector<double>              alpha;
    bool                                alpha_given = false;
    std::vector<dealii::Vector<double>> u;
    /** summary.json under construction. */
    Summary     summary;
    bool        converged              = false;
    bool        equilibrium_impossible = false;
    std::string message;
    Statistics  run_statistics;
    /** The counts and times of the solve that summary.json reports. */
    SolveWork work;
  };
} // namespace FetiContact
