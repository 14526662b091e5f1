#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/vector.h>

#include <feticontact/qp/mpgp.h>
#include <feticontact/qp/problem.h>
#include <feticontact/qp/projected_cg.h>
#include <feticontact/qp/separable_set.h>

#include <functional>

namespace FetiContact::QP
{
  /** Parameters of SMALBE-M. Zero for a scale-dependent value means "choose it" (see smalbe()).
   */
  struct SMALBEParameters
  {
    /** ε_g: stop when ‖g^P‖ ≤ ε_g ‖h‖ (and the feasibility test holds). */
    double tolerance = 1e-8;
    /** ε_f: stop when ‖Gλ − e‖ ≤ ε_f ‖e‖ (‖G‖ ‖λ‖ when e = 0). */
    double       feasibility_tolerance = 1e-8;
    unsigned int max_outer_iterations  = 500;
    /** Largest number of inner solver calls per outer iteration (see smalbe()). */
    unsigned int max_inner_calls = 20;
    /** ρ > 0, the penalty. 0: ‖F‖/‖G‖² (= ‖F‖ for normalized G). */
    double rho = 0;
    /** M_0 > 0. 0: M_0 = M0_factor · ρ ‖G‖. */
    double M0        = 0;
    double M0_factor = 1;
    /** β_M > 1: M ← M/β_M when the Lagrangian did not increase enough. */
    double beta_M = 10;
    /**
     * s ∈ (0, 2): the multiplier update μ ← μ + sρ(Gλ − e). 1 is SMALBE as published (Dostál),
     * with its bound on the number of outer iterations. s > 1 over-relaxes the update, as in the
     * method of multipliers, which converges for s ∈ (0, 2) when the inner problems are solved
     * exactly. In the projector variant without active constraints the Hessian is ρ on the
     * range of Gᵀ, and one update with s = 1 and an exact inner solve removes Gλ − e (s
     * overshoots by s − 1); with active constraints ‖Gλ − e‖ falls by a fixed factor per outer
     * iteration, which s > 1 can improve.
     */
    double multiplier_step = 1;
    /**
     * c ∈ (0, 1]: an inner solve stops no later than at ‖g^P‖ ≤ c ε_g ref_g (the floor of the
     * adaptive precision). With c = 1 the inner solves stop at the final gradient tolerance; when
     * ‖Gλ − e‖ is then still above ε_f, a multiplier update changes the gradient by less than
     * that floor, the inner solver returns without a step and SMALBE stalls (seen at
     * ‖Gλ − e‖ ≈ 5e-8 for a body held only by frictionless contact on a graded mesh,
     * prm/hertz.prm; c = 0.1 converges there in 12 outer iterations).
     */
    double inner_floor = 1;
    /**
     * The floor c is divided by 10 (down to 1e-4 c) whenever ‖Gλ − e‖ has not reached a new
     * minimum for this many outer iterations: the stall above, detected instead of avoided, so
     * that runs that never stall keep their path.
     */
    unsigned int stall_iterations = 10;
    /** η > 0. 0: η = eta_factor · ‖h‖. */
    double eta        = 0;
    double eta_factor = 0.1;
    /** ‖F‖ and ‖G‖ if known (0: power method with norm_iterations steps). */
    double       F_norm = 0, G_norm = 0;
    unsigned int norm_iterations = 10;
    /**
     * Options of the default inner solver (MPGP on the whole set); its tolerance is set by
     * SMALBE, its step 0 means ᾱ = 1.9/(‖F‖ + ρ‖G‖²) with the norms below: ‖F‖ + ρ‖G‖² bounds ‖F
     * + ρGᵀG‖ without power iterations on the inner operator.
     */
    MPGPParameters inner;

    /**
     * The penalty as a multiple of the norm of the FETI part of the Hessian, read from the
     * parameter file ('auto' keeps the value held when parsing); the caller turns it into rho.
     */
    double penalty_factor = 5;
    /** How the caller enforces Gλ = e around SMALBE (see EqualityConstraint). */
    enum class EqualityConstraint
    {
      projector, ///< homogenized, the Hessian PFP + ρQ (Farhat–Mandel–Roux)
      penalty    ///< the Hessian F + ρG̃ᵀG̃
    };
    EqualityConstraint equality_constraint = EqualityConstraint::projector;
    /** Which bound of ‖F + ρGᵀG‖ sets the inner MPGP's fixed step (see HessianNormBound). */
    enum class HessianNormBound
    {
      sum, ///< ‖F‖ + ρ‖G‖², valid for either equality constraint
      max  ///< max(‖F‖, ρ‖G‖²), valid for the projector only
    };
    HessianNormBound hessian_norm_bound = HessianNormBound::sum;

    /**
     * Declares, in the current subsection of @p prm: Maximum iterations, Penalty factor,
     * Multiplier step factor, Inner tolerance floor, Equality constraint, Hessian norm bound.
     * Entries that accept 'auto' leave the value that the object holds when parse_parameters()
     * reads them: the caller sets its automatic choices first.
     */
    static void
    declare_parameters(dealii::ParameterHandler &prm);

    /** Reads the entries of declare_parameters() from the current subsection of @p prm. */
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /**
   * SMALBE-M (semimonotonic augmented Lagrangian for bound and equality constraints with
   * adaptive precision control; Dostál, SIAM J. Numer. Anal. 2005) for
   *
   *     min ½λᵀFλ − λᵀh   s.t.  λ ∈ Ω,  Gλ = e,
   *
   * with G: R^m → R^k (Problem::G, and its transpose Problem::Gt). With the augmented
   * Lagrangian L(λ, μ, ρ) = ½λᵀFλ − λᵀh + μᵀ(Gλ − e) + ρ/2 ‖Gλ − e‖², whose Hessian in λ is
   * A = F + ρGᵀG and whose linear term is h − Gᵀμ + ρGᵀe, outer iteration k:
   *  1. λ_k ≈ argmin_{λ∈Ω} L(λ, μ_k, ρ), stopped when ‖g^P(λ)‖ ≤ max(min(M_k‖Gλ − e‖, η),
   *     ε_g ref_g). The floor ε_g ref_g (the final gradient tolerance) avoids solving to a
   *     precision the stopping test does not ask for. The default inner solver (MPGP) evaluates
   *     this rule after every step (MPGP::AdditionalData::stop_when; one application of G per
   * step). An InnerSolver takes a fixed tolerance: it gets the rule evaluated at its start (η if λ
   * is feasible there) and is called again, warm, while the rule fails at its result, at most
   *     max_inner_calls times or until a call makes no step or does not converge.
   *  2. Stop if ‖g^P(λ_k)‖ ≤ ε_g ref_g and ‖Gλ_k − e‖ ≤ ε_f ref_e.
   *  3. μ_{k+1} = μ_k + ρ(Gλ_k − e). (Then Fλ_k − h + Gᵀμ_{k+1} = g(λ_k, μ_k, ρ): μ_{k+1} is the
   *     multiplier that goes with λ_k, and the one returned.)
   *  4. If k > 0 and L(λ_k, μ_k, ρ) < L(λ_{k−1}, μ_{k−1}, ρ) + ρ/2 ‖Gλ_k − e‖²:
   *     M_{k+1} = M_k/β_M, else M_{k+1} = M_k.
   * After each inner solve the gradient gives the stopping test and L: the inner solver's own
   * (InnerReport::gradient; the default MPGP returns it), else one multiplication by A (counted).
   * It is passed to the next inner solve, corrected for the change of the linear term by the
   * multiplier update (g ← g + b_k − b_{k+1}, no multiplication). Then the
   * residual proposes a certificate of infeasibility, α = (e − Gλ_k)/‖e − Gλ_k‖ (for the
   * residual of least norm over Ω it is one whenever that norm is positive, and SMALBE's iterates
   * approach it when Gλ = e is infeasible): if αᵀe − σ_Ω(Gᵀα) > 1e-6 (|αᵀe| + |σ_Ω(Gᵀα)|),
   * no λ ∈ Ω satisfies Gλ = e and SMALBE stops with Statistics::infeasible.
   * ProjectorEnforcement makes the problem with PFP and Ph (P = I − GᵀG, e = 0).
   *
   * Every threshold is relative, so that multiplying F and h by s > 0 leaves λ
   * and the iteration counts unchanged and multiplies μ by s, and scaling G and e leaves λ
   * unchanged:
   *  - ref_g = ‖h‖ (‖F‖‖λ‖ if h = 0), never below the rounding level 64 ε_mach ‖A‖‖λ‖/ε_g;
   *  - ref_e = ‖e‖, never below 64 ε_mach ‖G‖‖λ‖/ε_f; if e = 0, ref_e = ‖G‖‖λ‖: ‖Gλ‖ cannot be
   *    small in any absolute sense, only against the size ‖G‖‖λ‖ of the terms it sums;
   *  - ρ = ‖F‖/‖G‖²: the penalty term ρGᵀG then has the norm of F (for G with orthonormal rows,
   *    ρ = ‖F‖ as in Dostál's experiments), invariant under G ← sG;
   *  - M_0 = ρ‖G‖ = ‖F‖/‖G‖: M converts a feasibility error into a gradient, and
   *    ‖ρGᵀ(Gλ − e)‖ ≤ ρ‖G‖ ‖Gλ − e‖ is the gradient an infeasibility ‖Gλ − e‖ causes; this is
   *    Dostál's M_0 = 1 for ‖F‖ = ‖G‖ = 1;
   *  - η = 0.1 ‖h‖.
   * ‖F‖ and ‖G‖ are power-method estimates (times 1.05) unless given. Without constraints
   * (k = 0 or G = 0) ρ = ‖F‖ and M_0 = ‖F‖ (they have no effect then).
   *
   * An object with its AdditionalData and Statistics. The inner solver is MPGP with
   * AdditionalData::inner, or one given by set_inner_solver() (block Gauss–Seidel in
   * Algorithms 1 and 2).
   */
  template <typename VectorType>
  class SMALBE
  {
  public:
    /**
     * What an inner solver of SMALBE reports: a SolverReport, and optionally the gradient
     * Aλ − b at the λ it returns (empty: not known, SMALBE multiplies by A itself).
     */
    struct InnerReport : SolverReport
    {
      InnerReport(const SolverReport &report = SolverReport())
        : SolverReport(report)
      {}
      /** Aλ − b at the returned λ, or empty. */
      VectorType gradient;
      /**
       * For inner solvers that change the set Ω while they solve (the combined loop of
       * Algorithm 2 updates the disc radii): whether Ω is that of the previous call. The M test
       * L(λ_k, μ_k) ≥ L(λ_{k−1}, μ_{k−1}) + ρ/2 ‖Gλ_k − e‖² compares the Lagrangians of two
       * iterations and says something about M only if both minimize over the same set; while the
       * radii move, a larger radius lowers the minimum of L, the test fails for that reason alone,
       * and M (with it the inner precision) would fall by β_M for nothing.
       */
      bool same_set = true;
      /**
       * Whether Ω is final: a certificate of infeasibility for a set that is still changing (the
       * radii of Algorithm 2 before λ_N has settled) proves nothing about the final one, so SMALBE
       * tests one only when this holds.
       */
      bool final_set = true;
      /**
       * Whether the solve ended at its iteration limit without converging (for the stall test
       * of Statistics::inner_stalled).
       */
      bool capped = false;
    };

    /**
     * An inner QP solver of SMALBE: approximately solves min ½λᵀAλ − bᵀλ over λ ∈ Ω, starting from
     * λ and overwriting it, until ‖g^P(λ)‖ ≤ tolerance (absolute). A is the Hessian F + ρGᵀG of
     * the augmented Lagrangian; the solver must call it for every multiplication (SMALBE counts
     * the calls) and knows the set Ω by itself (it captures it). @p gradient is Aλ − b at the λ
     * passed, or empty when SMALBE does not know it; a solver may use it instead of its first
     * multiplication (MPGP does), and may return the gradient at its result in
     * InnerReport::gradient, which saves SMALBE the multiplication that evaluates its stopping
     * test and the Lagrangian after the inner solve. A SolverReport converts to an InnerReport
     * without a gradient.
     */
    using InnerSolver = std::function<InnerReport(const Operator<VectorType> &A,
                                                  const VectorType           &b,
                                                  VectorType                 &lambda,
                                                  const double                tolerance,
                                                  const VectorType           &gradient)>;

    /** State of SMALBE after one outer iteration, for the monitor. */
    struct Step
    {
      /** k, counted from 0. */
      unsigned int outer_iteration = 0;
      /** Inner solver steps in this outer iteration, and the inner solver calls. */
      unsigned int inner_iterations = 0, inner_calls = 0;
      /** Multiplications by F + ρGᵀG so far. */
      unsigned int hessian_multiplications = 0;
      /** ‖g^P(λ_k, μ_k, ρ)‖ and ‖Gλ_k − e‖ over their references (see smalbe()). */
      double relative_gradient = 0, relative_feasibility = 0;
      /** L(λ_k, μ_k, ρ). */
      double lagrangian = 0;
      /** M_k (the one used in this inner solve); whether it was divided by β_M afterwards. */
      double M           = 0;
      bool   M_decreased = false;
    };

    /** The parameters: all numbers, set from a parameter file. */
    using AdditionalData = SMALBEParameters;

    /** What SMALBE reports. iterations = outer iterations; relative_residual = relative_gradient.
     */
    struct Statistics : SolverReport
    {
      /** How often the floor of the inner precision was lowered (AdditionalData::stall_iterations).
       */
      unsigned int floor_reductions = 0;
      /**
       * Whether SMALBE stopped, not converged, because its inner solves stalled: three outer
       * iterations in a row whose inner MPGP solve (the default inner solver) ended at its
       * iteration limit without bringing ‖g^P‖ 1 % below the least value of the previous such
       * solves or ‖Gλ − e‖ 1 % below its value at the previous one (the limit would otherwise be
       * spent again in every one of up to AdditionalData::max_outer_iterations).
       */
      bool inner_stalled = false;
      /** Inner solver steps and calls summed over all outer iterations. */
      unsigned int inner_iterations = 0, inner_calls = 0;
      /** Multiplications by F spent on the estimate of ‖F‖ (not in hessian_multiplications). */
      unsigned int norm_estimate_multiplications = 0;
      /** Final ‖g^P(λ, μ_k, ρ)‖/ref_g and ‖Gλ − e‖/ref_e (see smalbe()). */
      double relative_gradient = 0, relative_feasibility = 0;
      /** ρ, the final M, and the norm estimates used. */
      double rho = 0, M = 0, F_norm = 0, G_norm = 0;
      /** μ, the multiplier of Gλ = e (a copy of the output argument). */
      dealii::Vector<double> mu;
      /**
       * Whether SMALBE stopped because Gλ = e has no solution in Ω: α = e − Gλ_k of some outer
       * iteration satisfied αᵀe > σ_Ω(Gᵀα) (SeparableSet::support), so that every λ ∈ Ω has
       * αᵀ(Gλ − e) < 0. In FETI terms: the loads do more work on the rigid motion α than the
       * multipliers allowed by Ω can absorb, so the floating subdomains cannot be in equilibrium.
       * certificate_work = αᵀe and certificate_support = σ_Ω(Gᵀα) (with ‖α‖ = 1).
       */
      bool                   infeasible          = false;
      double                 certificate_work    = 0;
      double                 certificate_support = 0;
      dealii::Vector<double> certificate; ///< α (empty unless infeasible)
    };


    /** With the default AdditionalData. */
    SMALBE();

    explicit SMALBE(const AdditionalData &data);

    /** Replaces the default inner solver (MPGP with AdditionalData::inner on the set). */
    void
    set_inner_solver(InnerSolver solver);

    /** Called after every outer iteration. */
    void
    set_monitor(std::function<void(const Step &)> monitor);

    /** The parameters, e.g. to change the tolerances between solves. */
    AdditionalData &
    data();

    /**
     * Solves @p problem (its Hessian, linear term, set, G and e; for the projector variant the
     * problem that ProjectorEnforcement makes).
     *
     * @param lambda in: λ₀ (projected onto Ω by the inner solver); out: λ.
     * @param mu     in: μ₀ (size k, or empty for 0); out: μ.
     */
    Statistics
    solve(const Problem<VectorType> &problem, VectorType &lambda, dealii::Vector<double> &mu);

  private:
    /** ‖F‖, ‖G‖, ρ, M₀, η and the bound of ‖A‖. */
    void
    choose_scales();
    /** y = A x with A = F + ρGᵀG (or the problem's augmented Hessian), counted. */
    void
    apply_A(const VectorType &x, VectorType &y);
    /** r = Gλ − e; returns ‖r‖. */
    double
    residual();
    /** The reference of ‖g^P‖ at x: ‖h‖ (‖F‖‖x‖ if h = 0), floored at the rounding level. */
    double
    gradient_reference(const VectorType &x) const;
    /** The reference of ‖Gx − e‖: ‖e‖ (‖G‖‖x‖ if e = 0), floored at the rounding level. */
    double
    feasibility_reference(const VectorType &x) const;
    /** The inner stopping rule at x: max(min(M‖Gx − e‖, η), c ε_g ref_g). */
    double
    inner_target(const VectorType &x);
    /** b = h − Gᵀ(μ − ρe), and the known gradient corrected for its change. */
    void
    update_linear_term();
    /** MPGP with the inner stopping rule evaluated at every step. */
    InnerReport
    default_inner_solve(const VectorType &b, const double tolerance);
    /** Step 1: the inner solves of one outer iteration; whether the last one was capped. */
    bool
    inner_solves(Step &step, InnerReport &last);
    /** Lowers the floor of the inner precision when ‖Gλ − e‖ stalls. */
    void
    watch_feasibility();
    /** L(λ, μ_k, ρ) = ½λᵀ(g − b) − μᵀe + ρ/2‖e‖² with g = Aλ − b. */
    double
    lagrangian() const;
    /** Whether −r/‖r‖ proves Gλ = e infeasible in Ω (then recorded in the statistics). */
    bool
    infeasibility_proved();

    AdditionalData                    additional_data;
    InnerSolver                       inner_solver;
    std::function<void(const Step &)> monitor;

    // The state of the current solve.
    const Problem<VectorType> *problem = nullptr;
    VectorType                *lambda  = nullptr;
    dealii::Vector<double>    *mu      = nullptr;
    Statistics                 statistics;
    unsigned int               m = 0, k = 0;
    double F_norm = 0, G_norm = 0, rho = 0, M = 0, eta = 0, A_norm = 0, h_norm = 0, e_norm = 0;
    double floor = 1, feasibility = 0, norm_gP = 0, best_feasibility = 0;
    unsigned int           since_best    = 0;
    bool                   eta_exhausted = false;
    dealii::Vector<double> Gx, Gx_e, r;
    VectorType             GtGx, b, Gtv, g, gP, g_known;
  };
} // namespace FetiContact::QP
