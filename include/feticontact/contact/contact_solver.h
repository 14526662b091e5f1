#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/contact/contact_rows.h>
#include <feticontact/contact/contact_solver_parameters.h>
#include <feticontact/contact/load_balance.h>
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
   * The contact solvers of DESIGN.md §3 on the FETI dual problem
   *
   *   min ½λᵀFλ − λᵀh  s.t.  λ_N ≥ 0,  ‖λ_T,k‖ ≤ g_k,  λ_E free,  Gλ = e,
   *
   * λ = [λ_T; λ_N; λ_E] as in DualLayout. Frictionless zones have no λ_T. Tresca: g given.
   * Coulomb: g = F λ_N by successive approximations (MSA) from g = ∞ (the first MSA step is
   * sticking contact, solvable also for a body held by friction only), with relaxation
   * g ← (1 − ω) g + ω F λ_N, MSA step j solved to max(ε_QP, c · change_{j−1}) (inexact MSA):
   *
   * - Algorithm 1: each MSA step is the Tresca problem solved by SMALBE whose inner problem is
   *   split by block Gauss–Seidel: MPRGP on λ_c = [λ_N; λ_E] (λ_T fixed), then KPG (MPGP on the
   *   discs) on λ_T.
   * - Algorithm 2 (the seed's): MSA and the augmented Lagrangian in one loop: per SMALBE
   *   iteration one MPRGP solve for λ_c, the radii set to F λ_N of the new λ_N, one KPG solve for
   *   λ_T, one multiplier update; until the slip bound agrees with F λ_N.
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
   * QP (n_A^QPQ) as the seed does; the MPGP and polygonal variants count under `bound` when no
   * split exists (the product set).
   */
  class ContactSolver
  {
  public:
    struct Result
    {
      dealii::Vector<double> lambda;
      /** The multiplier μ̃ of G̃λ = ẽ (orthonormalized); α = −PᵀL⁻ᵀμ̃ in the primal recovery. */
      dealii::Vector<double> mu;
      unsigned int           outer_iterations  = 0; ///< Iter: MSA steps (Algorithm 2: loops)
      unsigned int           smalbe_iterations = 0;
      unsigned int           n_bound = 0, n_disc = 0;
      /** MPGP's steps summed over all its calls (QP::MPGP::Statistics): conjugate gradient,
       *  expansion and proportioning steps, and of the projected CG expansions those that
       *  increased the energy and were replaced by the fixed step, and the steps whose
       *  gradient was updated recursively (QP::MPGP::AdditionalData::recursive_gradient_tolerance).
       */
      unsigned int cg_steps = 0, expansion_steps = 0, proportioning_steps = 0,
                   expansion_fallbacks = 0, recursive_gradient_updates = 0;
      bool converged = false;

      void
      count_steps(const QP::MPGP::Statistics &r)
      {
        cg_steps += r.cg_steps;
        expansion_steps += r.expansion_steps;
        proportioning_steps += r.proportioning_steps;
        expansion_fallbacks += r.expansion_fallbacks;
        recursive_gradient_updates += r.recursive_gradient_updates;
      }
      /**
       * SMALBE proved that no λ within the current bounds balances the loads on the floating
       * subdomains (QP::SMALBE::Statistics::infeasible): no equilibrium exists with these slip
       * bounds, e.g. tangential loads above F × the normal force on a body held only by contact.
       */
      bool        no_equilibrium = false;
      std::string message;
    };

    ContactSolver(const DualProblem               &dual,
                  const DualLayout                &layout,
                  const std::vector<ContactNode>  &nodes,
                  const Parameters::ContactSolver &parameters,
                  std::ostream                    &out,
                  std::ostream                    *history);

    /** The problems hold operators that refer to this object: not copyable. */
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

  private:
    /**
     * Whether the equilibrium test proves that the current slip bounds cannot hold the bodies;
     * then @p result carries "no equilibrium" and its message.
     */
    bool
    slip_bounds_cannot_hold(Result &result) const;

    /** solve() in the homogenized unknown λ̃ (result.lambda), μ of the problem SMALBE solves. */
    Result
    solve_homogenized();

    /**
     * Algorithm 2 for the current friction (F × friction_scale), warm from @p result, until the
     * slip bound changes by at most @p msa_tolerance.
     */
    void
    solve_combined(Result &result, const double msa_tolerance);
    /**
     * MSA (Algorithm 1, MPGP, polygonal) for the current friction, warm from @p result; a
     * @p cold_start begins with the sticking problem (g = ∞), else with g = F λ_N.
     */
    void
    solve_msa(Result &result, const double msa_tolerance, const bool cold_start);

    /** λ̃ + λ₀. */
    dealii::Vector<double>
    total(const dealii::Vector<double> &lambda_tilde) const;

    /** The slip bound candidate F λ_N per node (0 where F = 0). */
    std::vector<double>
    coulomb_bound(const dealii::Vector<double> &lambda) const;
    /** Sets the tangential constraints for the slip bounds g. */
    void
    set_slip_bounds(const std::vector<double> &g);
    /** One SMALBE solve for the current slip bounds, warm-started from λ, μ. */
    QP::SMALBE::Statistics
    solve_tresca(dealii::Vector<double> &lambda, dealii::Vector<double> &mu, Result &result);
    /** MPGP's options from the parameters (steps, ᾱ = 1.9/‖Hessian‖, discs, expansion), shared
     *  by SMALBE's inner solves and the block Gauss–Seidel sweeps; the tolerance is the caller's.
     */
    QP::MPGP::AdditionalData
    mpgp_options() const;
    /** The block Gauss–Seidel inner solver (Algorithm 1; Algorithm 2 updates the radii in it). */
    QP::SolverReport
    gauss_seidel(const QP::Operator           &A,
                 const dealii::Vector<double> &b,
                 dealii::Vector<double>       &lambda,
                 const double                  tolerance,
                 const bool                    update_radii,
                 Result                       &result);
    void
    history_row(const unsigned int            msa,
                const unsigned int            smalbe,
                const double                  feasibility,
                const double                  gradient,
                const double                  change,
                const dealii::Vector<double> &lambda,
                const unsigned int            inner);

    const DualProblem                                      &dual;
    const DualLayout                                       &layout;
    const std::vector<ContactNode>                         &nodes;
    const Parameters::ContactSolver                        &parameters;
    std::ostream                                           &out;
    std::ostream                                           *history;
    std::function<LoadBalance(const std::vector<double> &)> equilibrium_test;
    QP::SeparableSet                                        set; ///< Ω for all of λ
    QP::SeparableSet          set_c; ///< bounds and free part, λ_c = [λ_N; λ_E]
    QP::SeparableSet          set_t; ///< tangential part λ_T
    std::vector<unsigned int> disc_of_node;
    std::vector<double>       slip_bound;
    /** ‖G̃‖ (1, or 0 without rigid modes) and the penalty ρ. */
    double G_norm = 0, rho = 0;
    /**
     * v ← P v = v − G̃ᵀG̃ v with the coarse-problem calls of the Hessian PFP + ρQ that SMALBE
     * applies (the setup's estimates of ‖PFP‖ and tr(PFP) use it, so that they measure that
     * Hessian).
     */
    void
    apply_P(dealii::Vector<double> &v) const;
    /**
     * The norm of the FETI part of the Hessian that ρ and the bound of the Hessian's norm are
     * taken from, and that SMALBE gets as QP::SMALBE::AdditionalData::F_norm: ‖F‖ (10
     * multiplications by F), or with Penalty norm = projected F (projector variant) the estimate of
     * ‖PFP‖ from projected_norm_iterations multiplications by F, and then ‖F‖ is not estimated
     * (both in F_applications, not in n_A).
     */
    double                        feti_norm                 = 0;
    static constexpr unsigned int projected_norm_iterations = 10;
    /** Whether SMALBE uses the projector variant (then λ₀ ≠ 0 and e = 0). */
    bool projector = false;
    /**
     * The dual problem with orthonormalized equality constraints, min ½λᵀFλ − λᵀh over Ω with
     * G̃λ = ẽ; with the projector, its homogenization in λ̃ = λ − λ₀ and the projected problem
     * (PFP, Ph) that SMALBE solves (`problem`; without the projector `problem` = `original`).
     */
    QP::Problem                             original, homogeneous, problem;
    std::optional<QP::Homogenization>       homogenization;
    std::optional<QP::ProjectorEnforcement> projector_enforcement;
    /** λ₀ (zero without the projector). */
    dealii::Vector<double> lambda0;
    /** Per row of λ: 0 gluing and Dirichlet, 1 normal, 2 tangential (for λ₀, see there). */
    std::vector<unsigned int> row_tier;
    /** The QP tolerance of the current solve (inexact MSA: looser in early MSA steps). */
    double qp_tolerance = 0;
    /**
     * The bound of the Hessian's norm behind the fixed step ᾱ = 1.9/‖A‖ of the block solves:
     * ‖F‖ + ρ‖G̃‖², or max(‖F‖, ρ) for the projector variant (Hessian norm bound = max); ‖PFP‖
     * in place of ‖F‖ with Penalty norm = projected F.
     */
    double hessian_norm = 0;
    /**
     * QP::MPGP::AdditionalData::arc_scale: 0 (the norm bound), or with Arc preconditioner scale =
     * mean diagonal the estimate of tr(A)/m of the Hessian, from arc_scale_probes multiplications
     * by F (in F_applications, not in n_A).
     */
    double                        arc_scale        = 0;
    static constexpr unsigned int arc_scale_probes = 10;
    /** λ after the last inner solve (for the status counts of the history). */
    dealii::Vector<double> last_lambda;
    unsigned int           msa_iteration = 0;
    double                 last_change   = 0;
    /** Radius updates inside the combined loop of Algorithm 2 (for InnerReport::final_set). */
    unsigned int radius_updates = 0;
    /** The stage of the continuation in F: the friction coefficients are multiplied by it. */
    double friction_scale = 1;
  };
} // namespace FetiContact
