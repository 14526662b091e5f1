#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/contact/combined_loop.h>
#include <feticontact/contact/contact_rows.h>
#include <feticontact/contact/contact_solver_parameters.h>
#include <feticontact/contact/friction_law.h>
#include <feticontact/contact/load_balance.h>
#include <feticontact/contact/tresca_problem.h>
#include <feticontact/feti/dual_problem.h>
#include <feticontact/qp/mpgp.h>
#include <feticontact/qp/separable_set.h>
#include <feticontact/qp/smalbe.h>
#include <feticontact/qp/transforms.h>

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * The contact solvers of doc/formulation.md ("Algorithms") on the FETI dual problem
   *
   *   min ½λᵀFλ − λᵀh  s.t.  λ_N ≥ 0,  ‖λ_T,k‖ ≤ g_k,  λ_E free,  Gλ = e,
   *
   * λ = [λ_T; λ_N; λ_E] as in DualLayout. Frictionless zones have no λ_T. Tresca: g given.
   * Coulomb: g = μ λ_N by successive approximations (MSA) from g = ∞ (the first MSA step is
   * sticking contact, solvable also for a body held by friction only), with relaxation
   * g ← (1 − ω) g + ω μ λ_N, MSA step j solved to max(ε_QP, c · change_{j−1}) (inexact MSA):
   *
   * - Algorithm 1: each MSA step is the Tresca problem solved by SMALBE whose inner problem is
   *   split by block Gauss–Seidel: MPRGP on λ_c = [λ_N; λ_E] (λ_T fixed), then KPG (MPGP on the
   *   discs) on λ_T.
   * - Algorithm 2 (the paper's): MSA and the augmented Lagrangian in one loop: per SMALBE
   *   iteration one MPRGP solve for λ_c, the radii set to μ λ_N of the new λ_N, one KPG solve for
   *   λ_T, one multiplier update; until the slip bound agrees with μ λ_N.
   * - mpgp: each MSA step by SMALBE with one MPGP over the product of bounds and discs.
   * - polygonal: the disc replaced by a regular 2s-gon, s multipliers per node in boxes
   *   |λ_j| ≤ g sin(π/2s) (the polygon's vertices lie on the circle ‖λ_T‖ = g), so MPRGP only.
   *
   * With `Equality constraint = projector` (the default) the problem is homogenized first:
   * λ = λ₀ + λ̃ with λ₀ = G̃ᵀẽ the least-norm solution of Gλ = e, so that G̃λ̃ = 0; the bounds
   * and disc centres shift by −λ₀ (λ̃_N ≥ −λ₀_N, ‖λ̃_T + λ₀_T‖ ≤ g) and SMALBE works with the
   * projected Hessian PFP + ρQ (QP::ProjectorEnforcement). Everything reported (λ, the
   * slip bounds, the statuses) is in terms of λ = λ₀ + λ̃.
   *
   * Counts the multiplications by the Hessian F + ρGᵀG in the bound QP (n_A^QPP) and in the disc
   * QP (n_A^QPQ) as the paper does; the MPGP and polygonal variants count under `bound` when no
   * split exists (the product set).
   *
   * The QP of one friction step (the problem with given slip bounds, its transforms and SMALBE)
   * is a TrescaProblem; Algorithm 2 is a CombinedLoop; this class holds the friction law, MSA
   * with its slip-bound update, the continuation in μ, the choice of algorithm and the record of
   * the iterations (Result::history).
   * The iterates and counts do not depend on the number of ranks.
   */
  class ContactSolver
  {
  public:
    /** One row of the iteration history: the state after a SMALBE iteration. */
    struct HistoryRow
    {
      /** The MSA step (0 for Algorithm 2 and for one Tresca QP) and the SMALBE iteration. */
      unsigned int msa_iteration = 0, smalbe_iteration = 0;
      /** ‖Gλ − e‖ and ‖g^P‖, relative (QP::SMALBE::Step). */
      double feasibility = 0, projected_gradient = 0;
      /** The relative change of the slip bound of the last update. */
      double slip_bound_change = 0;
      /** Open, stick and slip nodes (contact_status()). */
      unsigned int open = 0, stick = 0, slip = 0;
      /** The inner solver's steps in this SMALBE iteration. */
      unsigned int inner_iterations = 0;
    };

    struct Result
    {
      DualVector lambda;
      /** The multiplier ν of Gλ = e; α = −ν in the primal recovery. */
      dealii::Vector<double> mu;
      unsigned int           outer_iterations  = 0; ///< Iter: MSA steps (Algorithm 2: loops)
      unsigned int           smalbe_iterations = 0;
      unsigned int           n_bound = 0, n_disc = 0;
      /** MPGP's steps summed over all its calls (TrescaProblem::Statistics). */
      unsigned int cg_steps = 0, expansion_steps = 0, proportioning_steps = 0,
                   expansion_fallbacks = 0, recursive_gradient_updates = 0;
      bool converged = false;
      /**
       * SMALBE proved that no λ within the current bounds balances the loads on the floating
       * subdomains (QP::SMALBE::Statistics::infeasible), or the load-balance test that
       * the slip bounds of an MSA step cannot hold the bodies: no equilibrium exists with these
       * slip bounds, e.g. tangential loads above μ × the normal force on a body held only by
       * contact.
       */
      bool        no_equilibrium = false;
      std::string message;
      /** Every SMALBE iteration, in order (written to history.csv by the caller). */
      std::vector<HistoryRow> history;
    };

    /**
     * The solver for the dual problem @p dual with the contact rows of @p layout for @p nodes,
     * the nodes whose rows this rank holds (hold_contact_nodes(); TrescaProblem refuses others);
     * progress goes to @p out, the history into Result::history (write_history()).
     */
    ContactSolver(const DualProblem               &dual,
                  const DualLayout                &layout,
                  const std::vector<ContactNode>  &nodes,
                  const Parameters::ContactSolver &parameters,
                  std::ostream                    &out);

    /** The solvers hold references to this object: not copyable. */
    ContactSolver(const ContactSolver &) = delete;
    ContactSolver &
    operator=(const ContactSolver &) = delete;

    Result
    solve();

    /**
     * The test whether contact forces within Tresca sets (slip bounds by contact node, N) can
     * balance the loads on the free rigid motions of the bodies (LoadBalanceTest::tresca).
     * Given, every MSA step with finite slip bounds runs it before SMALBE: its proof of "no
     * equilibrium" holds for any decomposition, whereas SMALBE's certificate exists only where
     * the floating subdomains are whole bodies (with more subdomains SMALBE iterates up to its
     * limit instead). Algorithm 2 moves the radii inside SMALBE and is not tested.
     */
    void
    set_equilibrium_test(std::function<LoadBalance(const std::vector<double> &)> test);

    /** Writes the history rows as CSV with a header line. */
    static void
    write_history(const std::vector<HistoryRow> &rows, std::ostream &csv);

  private:
    /**
     * Whether the equilibrium test proves that the current slip bounds cannot hold the bodies;
     * then @p result carries "no equilibrium" and its message.
     */
    bool
    slip_bounds_cannot_hold(Result &result) const;

    /** solve() in the homogenized unknown λ̃ (result.lambda), ν of the problem SMALBE solves. */
    Result
    solve_homogenized();
    /** Frictionless or Tresca: one QP. */
    void
    solve_one_qp(Result &result);
    /**
     * MSA (Algorithm 1, MPGP, polygonal) for the current friction, warm from @p result; a
     * @p cold_start begins with the sticking problem (g = ∞), else with g = μ λ_N.
     */
    void
    solve_msa(Result &result, const double msa_tolerance, const bool cold_start);
    /** One MSA step: the equilibrium test, then the Tresca QP; false if it proved no equilibrium.
     */
    QP::SMALBE<DualVector>::Statistics
    msa_step(Result &result, const double tolerance);

    /** The slip bound candidate μ λ_N per node (0 where μ = 0), times the continuation stage. */
    std::vector<double>
    coulomb_bound(const DualVector &lambda) const;
    /** The monitor of the SMALBE iterations: a history row and a log line. */
    TrescaProblem::Monitor
    monitor(Result &result);

    const DualLayout                                       &layout;
    const std::vector<ContactNode>                         &nodes;
    const Parameters::ContactSolver                        &parameters;
    std::ostream                                           &out;
    std::function<LoadBalance(const std::vector<double> &)> equilibrium_test;
    FrictionLaw                                             law;
    TrescaProblem                                           tresca;
    CombinedLoop                                            combined;
    /** The current MSA step (0 outside MSA). */
    unsigned int msa_iteration = 0;
    /** The relative change of the slip bound in the last MSA step. */
    double last_change = 0;
    /** The QP tolerance of the current solve (inexact MSA: looser in early MSA steps). */
    double qp_tolerance = 0;
    /** The stage of the continuation in μ: the friction coefficients are multiplied by it. */
    double friction_scale = 1;
  };
} // namespace FetiContact
