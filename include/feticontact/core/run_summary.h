#pragma once

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <feticontact/base/json_writer.h>
#include <feticontact/contact/contact_solver.h>
#include <feticontact/contact/contact_state.h>
#include <feticontact/contact/load_balance.h>
#include <feticontact/core/memory_estimate.h>
#include <feticontact/core/summary.h>
#include <feticontact/feti/dual_problem.h>
#include <feticontact/postprocessing/hertz_comparison.h>
#include <feticontact/scene/body.h>
#include <feticontact/scene/scene_parameters.h>
#include <feticontact/subdomain/subdomain.h>

#include <memory>
#include <mpi.h>
#include <optional>
#include <vector>

namespace FetiContact
{
  /** The counts and times of a run's solve that summary.json reports. */
  struct SolveWork
  {
    /** The outer iterations of the contact solver, or the iterations of projected CG. */
    unsigned int iterations = 0;
    /** The Hessian multiplications of the bound and of the disc QPs (contact solver). */
    unsigned int n_bound = 0, n_disc = 0;
    /** Time in and number of applications of F up to the end of the solve. */
    double       F_time         = 0;
    unsigned int F_applications = 0;
    /** Of F_time, the time in this rank's subdomains. */
    double F_local_time = 0;
    /** Time in and number of applications of the lumped preconditioner (part of the solve). */
    double       preconditioner_time         = 0;
    unsigned int preconditioner_applications = 0;
    /** Wall time of the contact search, the mortar integrals and the contact rows (in setup). */
    double contact_rows_time = 0;

    /** Records the applications of F and of the preconditioner of @p dual so far. */
    void
    record_applications(const DualProblem &dual);
  };

  /** What a refinement study tabulates of a run (RefinementStudy). */
  struct RunStatistics
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

  /**
   * The leading members of summary.json (doc/summary_json.md), made from the parts of a run:
   * the outcome and the sizes, the Hessian multiplications, how the run was made (ranks,
   * threads, the FETI variant), the times of the phases and of the parts of the solve, the peak
   * memory with its estimate, the exchanges of one application of F and the local work per rank;
   * and the members of the load-balance test and of the contact solver.
   */
  namespace RunSummary
  {
    /** The parts of a solved run that the leading members are made of. */
    struct Run
    {
      MPI_Comm                                  comm;
      const Parameters::Scene                  &parameters;
      const dealii::TimerOutput                &timer;
      const std::vector<std::unique_ptr<Body>> &bodies;
      /** This rank's subdomains. */
      const std::vector<Subdomain *> &owned;
      /** The first subdomain of every body, and the number of subdomains at the end. */
      const std::vector<unsigned int> &first_subdomain;
      /** The first rigid mode of every subdomain, and the number of modes at the end. */
      const std::vector<unsigned int> &mode_offset;
      const DualProblem               &dual;
      const DualLayout                &layout;
      const ContactState              &contact;
      const MemoryEstimate            &memory_estimate;
      const SolveWork                 &work;
      bool                             converged;
    };

    /**
     * Sets the leading members of @p run in @p summary, prints the lines of the times and of
     * the peak memory through @p pcout, and sets the members of @p statistics (all but Hertz's).
     * Collective.
     */
    void
    set_leading_members(Summary                    &summary,
                        const Run                  &run,
                        dealii::ConditionalOStream &pcout,
                        RunStatistics              &statistics);

    /**
     * The leading members of a run that stopped without equilibrium before the solve: not
     * converged, the numbers of subdomains, contact nodes and ranks.
     */
    void
    set_stopped_members(Summary           &summary,
                        const unsigned int n_subdomains,
                        const unsigned int n_contact_nodes,
                        const unsigned int n_ranks);

    /** The outcome of the load-balance test (summary.json: load_balance). */
    void
    set_load_balance(Summary &summary, const LoadBalance &balance);

    /**
     * The closing message of the contact solver, whether it proved that no equilibrium exists,
     * its SMALBE iterations and MPGP's steps by kind.
     */
    void
    set_contact_solver(Summary &summary, const ContactSolver::Result &result);
  } // namespace RunSummary
} // namespace FetiContact
