#pragma once

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/lac/vector.h>

#include <feticontact/base/json_writer.h>
#include <feticontact/base/output_files.h>
#include <feticontact/base/tee_stream.h>
#include <feticontact/contact/contact_geometry.h>
#include <feticontact/contact/contact_rows.h>
#include <feticontact/contact/load_balance.h>
#include <feticontact/core/memory_estimate.h>
#include <feticontact/feti/dual_problem.h>
#include <feticontact/feti/shared_local_work.h>
#include <feticontact/postprocessing/hertz_comparison.h>
#include <feticontact/scene/body.h>
#include <feticontact/scene/scene_parameters.h>
#include <feticontact/subdomain/subdomain.h>

#include <fstream>
#include <functional>
#include <memory>
#include <mpi.h>
#include <optional>
#include <sstream>
#include <vector>

namespace FetiContact
{
  /**
   * A run of the program on one parameter file: builds the bodies and their subdomains (this
   * rank's share), the FETI dual problem, solves it, recovers the displacements and writes the
   * output (log.txt, summary.json, ParaView files). Phases are timed with TimerOutput.
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
    struct Statistics
    {
      unsigned int n_primal = 0, n_contact_nodes = 0, outer_iterations = 0,
                   hessian_multiplications = 0;
      /** The smallest cell diameter of all bodies. */
      double h_min = 0;
      /** Wall time of the solve and of the whole run without output [s]. */
      double solve_time = 0, time_without_output = 0;
      /** Verification/Hertz, if enabled. */
      std::optional<HertzResult> hertz;
    };
    /** Available after run(). */
    const Statistics &
    statistics() const
    {
      return run_statistics;
    }

  private:
    void
    prepare_output_directory();
    void
    setup_bodies();
    /**
     * The contact nodes of every zone, and the test that contact forces within the friction
     * law's sets can balance the loads on the free rigid motions (LoadBalanceTest): a proof
     * of the contrary sets no_equilibrium() before any subdomain is built.
     */
    void
    setup_contact();
    /** summary.json of a run that stops in setup_contact() without equilibrium. */
    void
    write_no_equilibrium_summary();
    void
    distribute_subdomains();
    void
    build_subdomains();
    void
    factorize();
    void
    build_dual_problem();
    void
    solve();
    void
    solve_contact();
    void
    postprocess();
    /**
     * The independent check of a converged run: a solution whose @p value (a quantity of
     * summary.json, named by @p key) exceeds @p limit is no solution, whatever the solver's
     * residuals say; the run becomes not converged with a message naming the quantity.
     */
    void
    check_quantity(const std::string &key,
                   const std::string &description,
                   double             value,
                   double             limit);
    void
    write_summary();
    /** Renames every rank's result files to their final names, summary.json last. */
    void
    commit_results();
    /**
     * Runs @p write (on this rank) and makes an OutputError of any rank every rank's, so that
     * all ranks stop together.
     */
    void
    on_all_ranks(const std::function<void()> &write);
    /** Throws OutputError on every rank if rank 0's log.txt could not be written. */
    void
    check_log();

    MPI_Comm           comm;
    const unsigned int rank;
    const unsigned int n_ranks;
    Parameters::Scene  parameters;
    MemoryEstimate     memory_estimate; ///< of the run's peak, made before any mesh is built
    const std::string  effective_parameters, input;
    std::ofstream      log_file;
    /** This rank's result files, renamed to their final names at the end of run(). */
    ResultFiles result_files;
    /** summary.json, renamed after every other result file. */
    ResultFiles                summary_file;
    TeeStream                  tee;
    dealii::ConditionalOStream pcout;
    dealii::TimerOutput        timer;

    const dealii::FESystem<3>  fe;
    const dealii::MappingFE<3> mapping;

    std::vector<std::unique_ptr<Body>> bodies;
    std::vector<unsigned int>          first_subdomain; ///< per body, + total at the end
    /** Verification/Reference displacements, by body and vertex (empty: none). */
    std::vector<std::vector<dealii::Tensor<1, 3>>> reference_displacements;
    std::vector<unsigned int>                      owner; ///< rank of each subdomain
    /**
     * The reserves of the node's ranks: factors in shared memory, whose local work in every
     * multiplication by F the ranks share (FETI/Shared local work > 0, if possible).
     */
    std::unique_ptr<SharedLocalWork>        shared_work;
    std::vector<std::unique_ptr<Subdomain>> subdomains; ///< this rank's
    std::vector<Subdomain *>                owned;
    std::vector<unsigned int>               mode_offset;
    DualRows                                rows;
    std::vector<ContactNode>                contact_nodes;
    /** The load-balance test of the scene, for the pre-solve test and every MSA step. */
    std::unique_ptr<LoadBalanceTest> load_balance_test;
    std::vector<ContactTriangle>     contact_triangles;
    DualLayout                       layout;
    std::unique_ptr<DualProblem>     dual;

    dealii::Vector<double> lambda;
    /** Coefficients of the rigid modes in the primal recovery (contact: from the solver). */
    dealii::Vector<double>              alpha;
    bool                                alpha_given = false;
    std::vector<dealii::Vector<double>> u;
    JsonObject                          summary;
    bool                                converged              = false;
    bool                                equilibrium_impossible = false;
    std::string                         message;
    unsigned int                        iterations = 0;
    unsigned int                        n_bound = 0, n_disc = 0;
    Statistics                          run_statistics;
    /** Time in and number of applications of F up to the end of the solve. */
    double       solve_F_time         = 0;
    double       solve_F_local_time   = 0;
    unsigned int solve_F_applications = 0;
    /** Time in and number of applications of the lumped preconditioner (part of the solve). */
    double       solve_preconditioner_time         = 0;
    unsigned int solve_preconditioner_applications = 0;
  };
} // namespace FetiContact
