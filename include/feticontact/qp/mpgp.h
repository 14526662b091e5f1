#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/vector.h>

#include <feticontact/qp/problem.h>
#include <feticontact/qp/projected_cg.h>
#include <feticontact/qp/separable_set.h>

#include <functional>

namespace FetiContact::QP
{

  /**
   * An estimate of ‖A‖ (the largest eigenvalue of a symmetric positive semidefinite A) by the
   * power method: `iterations` multiplications by A (at least one) from a fixed pseudo-random
   * start vector (entry i the i-th number of std::minstd_rand(20120101), minus ½, by global index:
   * the same on any number of ranks), returning ‖A v‖ for the last unit iterate v. @p model gives
   * the vector layout. It is a lower bound of ‖A‖; callers add a safety factor. Returns 0 if A v =
   * 0.
   */
  template <typename VectorType>
  double
  estimate_norm(const Operator<VectorType> &A,
                const VectorType           &model,
                const unsigned int          iterations = 10);

  /**
   * An estimate of the mean diagonal entry tr(A)/n of a symmetric positive semidefinite A by
   * Hutchinson's method: the mean of vᵀAv/n over `probes` vectors v with independent entries
   * ±1 (at least one), drawn from a fixed pseudo-random sequence by global index (the same for
   * every call with the same n, so that the estimate is the same on every MPI rank, on any number
   * of ranks, and in every run). Unbiased;
   * its spread shrinks like 1/√probes. Returns 0 for n = 0.
   */
  template <typename VectorType>
  double
  estimate_mean_diagonal(const Operator<VectorType> &A,
                         const VectorType           &model,
                         const unsigned int          probes = 10);

  /** The parameters of MPGP that a parameter file sets (MPGP::AdditionalData adds the callbacks).
   */
  struct MPGPParameters
  {
    /** ε: stop when ‖g^P(x)‖ ≤ ε (absolute: the caller makes it relative, e.g. ε_rel ‖b‖). */
    double tolerance = 0;
    /** Largest number of steps (CG, expansion and proportioning steps together). */
    unsigned int max_iterations = 10000;
    /** Γ > 0 of the proportionality test ‖β‖² ≤ Γ² φ̃ᵀφ. */
    double gamma = 1;
    /**
     * ᾱ ∈ (0, 2/‖A‖], the fixed step of expansion and projected proportioning steps. 0: ᾱ =
     * 1.9/(1.05 ‖A‖_est) with ‖A‖_est = estimate_norm(A, n, norm_iterations).
     */
    double step = 0;
    /**
     * Step length of the projected proportioning step P_Ω(x − αβ) (β acting on a disc).
     * true (default): α = βᵀg/(βᵀAβ + Σ_k σ_k‖β_k‖²/r_k), the minimizer of the second-order model
     * of f along the arc α ↦ P_Ω(x − αβ) (σ_k = −g_k·ν_k > 0 on an active disc k whose β_k is
     * tangential; SeparableSet::arc_curvature); one more multiplication by A per such step.
     * false: α = ᾱ (Dostál–Kozubek); this step increases f when σ_k/r_k ≳ 2/ᾱ − ‖A‖ (small
     * discs pressed hard outwards, as at the edge of a contact zone with friction) and is then
     * replaced by P_Ω(x − ᾱg), which can stagnate (see tests/unit/qp_mpgp.cc). Either step is
     * replaced by P_Ω(x − ᾱg) if it increased f.
     */
    bool proportioning_line_search = true;
    /**
     * Rotations on active discs (SeparableSet::DiscMode::rotations): conjugate gradient steps
     * also move blocks along the circles of their active discs (projected back onto the circle,
     * the gradient recomputed: two multiplications by A per such step), conjugated with the
     * Hessian along the circles A + C (SeparableSet::add_arc_curvature); β keeps only the
     * inward normal part on discs, so proportioning steps are exact line searches. false: the
     * fixed-disc MPGP of Dostál–Kozubek (Kučera's KPG), where an active disc changes its angle
     * only by proportioning (gradient) steps, which converge like steepest descent once most
     * discs are active (the situation of contact with friction: most nodes slip).
     */
    bool disc_rotations = true;
    /**
     * With rotations: precondition the conjugate gradient steps by M = diag(1 on free
     * components, 1 + (σ_k/r_k)/a on the tangent of an active disc k pressed outwards with
     * σ_k; a = arc_scale): the curvature σ_k/r_k of small, strongly pressed circles (slipping
     * nodes with a small normal force, at the edge of a contact zone) otherwise dominates the
     * Hessian along them.
     */
    bool precondition_rotations = true;
    /**
     * The scale a of the rest of the Hessian in the preconditioner of the rotations,
     * diag(1 + (σ_k/r_k)/a) (SeparableSet::precondition_arcs). 0 (default): the bound of ‖A‖
     * behind the fixed step, 1.9/ᾱ. The entries of M on free components are 1, so M is the
     * Jacobi preconditioner of the Hessian along the circles when a is the typical diagonal entry
     * of A; ‖A‖ can exceed it by orders of magnitude (the FETI Hessian PFP + ρQ on the brick:
     * 71–98 times at H/h = 8, doc/performance.md), and then the curvature σ_k/r_k of small,
     * strongly pressed circles is underweighted by as much. The mean diagonal
     * (estimate_mean_diagonal) is the measured alternative.
     */
    double arc_scale = 0;
    /**
     * η ≥ 0 of the recursive gradient update after steps whose projection onto Ω moves the
     * iterate off its line: conjugate gradient steps along the circles of active discs (with
     * rotations) and projected conjugate gradient expansions. 0 (default): after such a step
     * x ← P_Ω(x − α_cg p) the gradient is recomputed, g ← Ax − b (the second multiplication of
     * the step). η > 0: instead g ← g − α_cg Ap, which leaves out A d for the return
     * d = P_Ω(x − α_cg p) − (x − α_cg p) onto Ω (on circles of second order in the rotation
     * angles); the error of g is bounded by the sum of (2/ᾱ)‖d‖ over the steps since the last
     * recomputation (2/ᾱ ≥ ‖A‖), and g is recomputed when that bound would exceed η‖g^P‖,
     * when the energy test on the updated gradient sees an increase of f, and before MPGP
     * stops, so that every stopping decision is made on the exact gradient.
     */
    double recursive_gradient_tolerance = 0;
    /** How an expansion step (the conjugate gradient step leaves Ω) adds constraints. */
    enum class Expansion
    {
      /**
       * Dostál–Schöberl: the feasible half step to the boundary of Ω, then the fixed step
       * P_Ω(x − ᾱφ). With ᾱ ≈ 2/‖A‖ small, this adds little more than the one constraint met
       * by the half step, so the number of expansions grows with the number of constraints that
       * become active (measured: about the number of open contact nodes).
       */
      fixed_step,
      /**
       * The whole conjugate gradient step projected, P_Ω(x − α_cg p) (the "projcg" expansion
       * with fallback of Kružík et al., "Active set expansion strategies in MPRGP algorithm",
       * Adv. Eng. Softw. 2020, as in PERMON's QPSMPGP), which adds every constraint that the
       * unconstrained step crosses; accepted only if f decreased, otherwise replaced by the
       * fixed_step expansion (one more multiplication).
       */
      projected_cg
    };
    Expansion expansion = Expansion::fixed_step;
    /** Power iterations for ᾱ when step = 0. */
    unsigned int norm_iterations = 10;
    /** Called after every step with (step number, ‖g^P‖). */
    std::function<void(unsigned int, double)> monitor;

    /** How the caller chooses arc_scale (once per problem; MPGP itself only reads arc_scale). */
    enum class ArcScale
    {
      norm_bound,   ///< 0 in arc_scale: the bound 1.9/ᾱ of ‖A‖
      mean_diagonal ///< tr(A)/n, estimated by estimate_mean_diagonal()
    };
    ArcScale arc_scale_estimate = ArcScale::norm_bound;

    /**
     * Declares, in the current subsection of @p prm, the entries Maximum iterations, Disc
     * rotations, Expansion step, Recursive gradient tolerance and Arc preconditioner scale,
     * with the defaults of a default-constructed AdditionalData. Entries that accept 'auto'
     * leave the value that the object holds when parse_parameters() reads them: the caller
     * sets its automatic choices first.
     */
    static void
    declare_parameters(dealii::ParameterHandler &prm);

    /** Reads the entries of declare_parameters() from the current subsection of @p prm. */
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /**
   * MPGP (modified proportioning with gradient projections; Dostál–Kozubek, Math. Program.
   * 2012; on intervals it is MPRGP of Dostál–Schöberl, Comput. Optim. Appl. 2005):
   *
   *     min ½ xᵀA x − bᵀx   s.t.  x ∈ Ω   (Ω a SeparableSet, A symmetric positive definite).
   *
   * From x = P_Ω(x₀), g = Ax − b, p = φ(x), until ‖g^P(x)‖ ≤ ε (or AdditionalData::stop_when):
   *  - if x is proportional, ‖β(x)‖² ≤ Γ² φ̃(x)ᵀφ(x) with the reduced free gradient
   *    φ̃(x) = (x − P_Ω(x − ᾱ φ(x)))/ᾱ: α_cg = gᵀp/pᵀAp, α_f = the largest feasible step along −p;
   *    if α_cg ≤ α_f a CG step x ← x − α_cg p, g ← g − α_cg Ap, p ← φ − (φᵀAp/pᵀAp) p; otherwise
   *    an expansion step x ← x − α_f p, g ← g − α_f Ap, x ← P_Ω(x − ᾱ φ(x)), g ← Ax − b, p ← φ;
   *  - otherwise a proportioning step: if β(x) vanishes on all discs, the exact line search along
   *    β (α = gᵀβ/βᵀAβ, cut at the feasible step so that a box's far end is respected); if β
   *    acts on an active disc (a line along β leaves the curved set), the projected step
   *    x ← P_Ω(x − αβ) with α from a second-order model of f along the projected arc, or α = ᾱ
   *    as in Dostál–Kozubek (AdditionalData::proportioning_line_search),
   *    replaced by x ← P_Ω(x − ᾱ g) if f increased beyond its rounding level (only the latter
   *    step is guaranteed to decrease f for ᾱ ≤ 2/‖A‖; the former needs
   *    ᾱ ≤ 2/(‖A‖ + σ_k/r_k), which fails on strongly curved discs: small r_k, large
   *    multiplier σ_k); then p ← φ.
   * This is the fixed-disc mode (AdditionalData::disc_rotations = false). With rotations (the
   * default) φ and β are those of SeparableSet::DiscMode::rotations: φ includes the tangential
   * gradient of active discs, β only the inward normal part (so the proportioning step is always
   * the exact line search), and a CG step that moves active discs follows their circles:
   * x ← P_Ω(x − α_cg p) with α_cg = gᵀp/(pᵀAp + Σ σ_k‖p_k‖²/r_k), g ← Ax − b (one more
   * multiplication), p ← z − γp with z = M⁻¹φ (AdditionalData::precondition_rotations) and γ of
   * Hestenes–Stiefel from the change of φ along the step, p transported to the new tangents;
   * such a step that increased f is replaced by P_Ω(x − ᾱg). The expansion step uses the
   * fixed-disc φ, whose projected step is guaranteed to decrease f.
   * Iterates are kept in Ω exactly (projected after every update, which changes them only at the
   * rounding level). gᵀp is evaluated as φᵀp (equal in exact arithmetic, free of the
   * cancellation of the normal parts of g on pressed discs). A CG direction with gᵀp ≤ 0 or
   * pᵀAp ≤ 0 is replaced by φ; pᵀAp ≤ 0 for p = φ ≠ 0 (A not positive definite) ends the solve
   * unconverged.
   *
   * An object with its AdditionalData (declared and parsed in a prm subsection of the caller's
   * choosing) and Statistics; solve() runs the iteration, whose steps are member functions:
   * conjugate_gradient_step(), expansion_step(), proportioning_step().
   */
  template <typename VectorType>
  class MPGP
  {
  public:
    /** The parameters of MPGP: those of a parameter file and the callbacks. */
    struct AdditionalData : MPGPParameters
    {
      AdditionalData() = default;

      /** @p parameters, without callbacks. */
      AdditionalData(const MPGPParameters &parameters)
        : MPGPParameters(parameters)
      {}

      /**
       * Preconditioning in face: a symmetric positive definite M ≈ A⁻¹ on the whole space
       * (empty: none). The conjugate gradient steps then use z = R_F M R_F φ, where R_F restricts
       * a vector to the current face (zero on active intervals and fixed discs, the tangent on
       * active discs with rotations: SeparableSet::free_gradient applied to M φ); with
       * precondition_rotations the arc factor D is applied as D^(−½) on both sides. Expansion and
       * proportioning steps, and the proportionality test, keep the unpreconditioned φ and β
       * (Dostál's MPRGP with preconditioning in face; Kružík, Horák, arXiv:2507.00617, 2025). The
       * conjugacy of the steps holds only within one face: every change of the active set
       * restarts from z.
       */
      Operator<VectorType> preconditioner;
      /**
       * An additional stopping test, evaluated at the start and after every step with (x, ‖g^P‖):
       * MPGP stops (converged) when it returns true or ‖g^P‖ ≤ tolerance. SMALBE uses it for its
       * inner stopping rule ‖g^P‖ ≤ min(M‖Gx − e‖, η), which depends on x.
       */
      std::function<bool(const VectorType &, double)> stop_when;
    };

    /**
     * What MPGP reports. `iterations` counts all steps; `hessian_multiplications` counts every
     * multiplication by A, including the norm_estimate_multiplications of the power method when
     * ᾱ was estimated; relative_residual = ‖g^P‖/‖b‖ (‖g^P‖ when b = 0).
     */
    struct Statistics : SolverReport
    {
      /** Conjugate gradient steps (x − α_cg p stayed in Ω). */
      unsigned int cg_steps = 0;
      /** Expansion steps (feasible half step, then P_Ω(x − ᾱ φ); or P_Ω(x − α_cg p)). */
      unsigned int expansion_steps = 0;
      /** Projected conjugate gradient expansions that increased f and were replaced. */
      unsigned int expansion_fallbacks = 0;
      /** Proportioning steps (along β: exact line search, or projected step with discs). */
      unsigned int proportioning_steps = 0;
      /**
       * Projected proportioning steps P_Ω(x − αβ) that increased f (the curvature of an active
       * disc) and were replaced by the projected gradient step P_Ω(x − ᾱ g).
       */
      unsigned int proportioning_fallbacks = 0;
      /**
       * Steps (along circles, or projected CG expansions) whose gradient was updated recursively
       * (AdditionalData::recursive_gradient_tolerance), each one multiplication by A fewer.
       */
      unsigned int recursive_gradient_updates = 0;
      /** Applications of AdditionalData::preconditioner (one per step). */
      unsigned int preconditioner_applications = 0;
      /** Multiplications by A spent on the power method (part of hessian_multiplications). */
      unsigned int norm_estimate_multiplications = 0;
      /** ‖g^P(x)‖ at the end. */
      double projected_gradient_norm = 0;
      /** The step ᾱ used. */
      double step = 0;
    };

    /** With the default AdditionalData. */
    MPGP();

    explicit MPGP(const AdditionalData &data);

    /**
     * Minimizes ½ xᵀA x − bᵀx over x ∈ Ω = @p set.
     *
     * @param x in: x₀ (any point, projected first); out: the last iterate.
     * @param gradient optional, in and out. In: Ax₀ − b if it has the size of b (else ignored);
     *   MPGP then starts without a multiplication, unless the projection of x₀ onto Ω moved it.
     *   Out: Ax − b at the last iterate, the gradient of the last stopping decision (SMALBE passes
     *   it from one inner solve to the next, corrected for the change of b).
     */
    Statistics
    solve(const Operator<VectorType> &A,
          const VectorType           &b,
          const SeparableSet         &set,
          VectorType                 &x,
          VectorType                 *gradient = nullptr);

    /** The parameters, e.g. to change the tolerance between solves. */
    AdditionalData &
    data();

  private:
    /** What a step did: moved x, only replaced the search direction by z, or broke down. */
    enum class Outcome
    {
      step,
      retry,
      breakdown
    };

    /** ᾱ (estimating ‖A‖ if AdditionalData::step = 0); false if A vanished on the start vector. */
    bool
    choose_step();
    /** x = P_Ω(x₀), g, φ, β and p = z at the start; uses the caller's gradient if valid. */
    void
    start(VectorType *gradient);
    /** w = A v, counted. */
    void
    multiply(const VectorType &v, VectorType &w);
    /** g = Ax − b, recomputed. */
    void
    recompute_gradient();
    /** φ, β, ‖g^P‖ and the preconditioned direction z at the current x and g. */
    void
    update_sets();
    /** Whether f increased from x_old to x beyond its rounding level. */
    bool
    increased() const;
    /** The gradient after x = P_Ω(x_old − α p): updated recursively (true) or recomputed. */
    bool
    gradient_after_projection(const double alpha);
    /** The fallback x ← P_Ω(x_old − ᾱ g_old), which decreases f for ᾱ ≤ 2/‖A‖. */
    void
    projected_gradient_step();
    /** ‖β‖² ≤ Γ² φ̃ᵀφ with φ̃ = (x − P_Ω(x − ᾱφ))/ᾱ. */
    bool
    proportional();
    /** The step along p: conjugate gradient or expansion. */
    Outcome
    step_along_p();
    /** x ← x − α_cg p (along the circles of active discs with rotations), then p conjugated. */
    void
    conjugate_gradient_step(const double alpha_cg, const double curvature, const bool arc);
    /** The expansion when the conjugate gradient step leaves Ω (α_f < α_cg). */
    void
    expansion_step(const double alpha_cg, const double alpha_f);
    /** The proportioning step along β. */
    Outcome
    proportioning_step();
    /** ‖g^P‖ ≤ tolerance or AdditionalData::stop_when. */
    bool
    stop() const;
    /** stop(), decided on the exact gradient. */
    bool
    done();

    AdditionalData additional_data;

    // The state of the current solve.
    const Operator<VectorType> *A   = nullptr;
    const VectorType           *b   = nullptr;
    const SeparableSet         *set = nullptr;
    VectorType                 *x   = nullptr;
    SeparableSet::DiscMode      mode{};
    Statistics                  statistics;
    double                      alpha_bar = 0, arc_scale = 0, norm_gP = 0, gradient_error = 0;
    bool                        precondition = false, in_face = false, p_is_phi = true;
    VectorType                  g, p, Ap, Hp, phi, beta, y, z, Mz, x_old, g_old, phi_old;
  };

} // namespace FetiContact::QP
