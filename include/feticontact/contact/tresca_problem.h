#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/contact/contact_rows.h>
#include <feticontact/contact/contact_solver_parameters.h>
#include <feticontact/feti/dual_problem.h>
#include <feticontact/feti/local_dual_rows.h>
#include <feticontact/qp/mpgp.h>
#include <feticontact/qp/separable_set.h>
#include <feticontact/qp/smalbe.h>
#include <feticontact/qp/transforms.h>

#include <array>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * @brief The FETI dual problem of contact with given slip bounds g (a problem with Tresca
   * friction), and its solution by SMALBE:
   *
   *   min ½λᵀFλ − λᵀh  s.t.  λ_N ≥ 0,  ‖λ_T,k‖ ≤ g_k,  λ_E free,  G̃λ = ẽ,
   *
   * with λ = [λ_T; λ_N; λ_E] as in DualLayout and G̃ the orthonormalized G. With `Equality
   * constraint = projector` (the default) the problem is homogenized
   * (QP::Homogenization<DualVector>): λ = λ₀ + λ̃ with the particular solution λ₀ of the coarse
   * problem, so that G̃λ̃ = 0; the bounds and disc centres shift by −λ₀ and SMALBE solves the
   * projected problem (QP::ProjectorEnforcement<DualVector>). Multipliers passed to solve() are λ̃;
   * total() and recover() map back. The inner solver is MPGP over the whole set (mpgp, polygonal)
   * or, for the paper's Algorithms 1 and 2, block Gauss–Seidel: MPRGP on λ_c = [λ_N; λ_E] with λ_T
   * fixed, then KPG (MPGP on the discs) on λ_T.
   *
   * Knows nothing of friction laws: the caller sets the slip bounds (set_slip_bounds()).
   *
   * Every rank holds the rows it adds up in F x (LocalDualRows). The contact nodes are those
   * whose rows this rank holds (hold_contact_nodes(): each node on one rank), and the slip bounds
   * and per-node results are theirs: no per-node array of all nodes is exchanged.
   */
  class TrescaProblem
  {
  public:
    /** Counts summed over all solves. */
    struct Statistics
    {
      /** Multiplications by the Hessian in the bound QP (n_A^QPP) and in the disc QP. */
      unsigned int n_bound = 0, n_disc = 0;
      /** SMALBE's outer iterations. */
      unsigned int smalbe_iterations = 0;
      /**
       * MPGP's steps (QP::MPGP<DualVector>::Statistics): conjugate gradient, expansion and
       * proportioning steps, the projected CG expansions that increased the energy and were
       * replaced, and the steps whose gradient was updated recursively.
       */
      unsigned int cg_steps = 0, expansion_steps = 0, proportioning_steps = 0,
                   expansion_fallbacks = 0, recursive_gradient_updates = 0;

      /** Adds the steps of one MPGP solve. */
      void
      count_steps(const QP::MPGP<DualVector>::Statistics &r);
    };

    /**
     * A set that moves inside the solve: Algorithm 2 updates the radii between the two blocks
     * of every Gauss–Seidel sweep. update() is called with λ̃ after the λ_c block;
     * unchanged() and final() after every inner solve tell SMALBE whether the set is that of the
     * previous inner solve and whether it is final (QP::SMALBE<DualVector>::InnerReport).
     */
    struct MovingSet
    {
      std::function<void(const DualVector &)> update;
      std::function<bool()>                   unchanged, final;
    };

    /** Called after every SMALBE iteration with its step and λ̃ after the inner solve. */
    using Monitor =
      std::function<void(const QP::SMALBE<DualVector>::Step &, const DualVector &lambda)>;

    /**
     * Sets up the problem: the transforms, the constraint set (all slip bounds 0), the norm
     * estimates, ρ and MPGP's scales (reported on @p out).
     */
    TrescaProblem(const DualProblem               &dual,
                  const DualLayout                &layout,
                  const std::vector<ContactNode>  &nodes,
                  const Parameters::ContactSolver &parameters,
                  std::ostream                    &out);

    /** The problems hold operators that refer to this object: not copyable. */
    TrescaProblem(const TrescaProblem &) = delete;
    TrescaProblem &
    operator=(const TrescaProblem &) = delete;

    /** Sets the slip bounds g (per contact node, in the units of its multipliers). */
    void
    set_slip_bounds(const std::vector<double> &g);

    /** The current slip bounds. */
    const std::vector<double> &
    slip_bounds() const;

    /**
     * One SMALBE solve to the relative @p tolerance for the current slip bounds, warm from
     * λ̃ = @p lambda and ν = @p nu (overwritten). @p moving_set: Algorithm 2 (one inner call per
     * SMALBE iteration, radii updated inside).
     */
    QP::SMALBE<DualVector>::Statistics
    solve(DualVector             &lambda,
          dealii::Vector<double> &nu,
          const double            tolerance,
          const Monitor          &monitor,
          const MovingSet        *moving_set = nullptr);

    /** λ = λ̃ + λ₀. */
    DualVector
    total(const DualVector &lambda_tilde) const;

    /** The normal force (N) of every contact node (of this rank) at λ̃. */
    std::vector<double>
    normal_forces(const DualVector &lambda_tilde) const;

    /**
     * The solution of the original problem from λ̃ and the ν of the problem SMALBE solved: λ₀
     * added, Gλ = e restored to rounding with a correction from the gluing rows, ν mapped back
     * from the projected and the orthonormalized problem to the multiplier of Gλ = e.
     */
    void
    recover(DualVector &lambda, dealii::Vector<double> &nu) const;

    /**
     * ‖next − previous‖ / ‖next‖ of two slip bounds of the nodes of all ranks (an infinite
     * previous entry, the unbounded discs of the first MSA step, counts as 0; 0 if next = 0),
     * from exact sums: the same bits on any number of ranks.
     */
    double
    relative_change(const std::vector<double> &previous, const std::vector<double> &next) const;

    /** Open, stick and slip nodes at λ̃ for the current slip bounds (contact_status()). */
    std::array<unsigned int, 3>
    status_counts(const DualVector &lambda_tilde) const;

    /**
     * The message for SMALBE's proof that no multiplier within the current bounds balances the
     * loads (QP::SMALBE<DualVector>::Statistics::infeasible), with the certificate in the original
     * variables.
     */
    std::string
    no_equilibrium_message(const QP::SMALBE<DualVector>::Statistics &report) const;

    /** k, the number of rows of G̃ (the size of ν). */
    unsigned int
    n_equality_constraints() const;

    /** The rows of the dual vectors this rank holds. */
    const LocalDualRows &
    local_rows() const
    {
      return rows;
    }

    /** The counts so far. */
    const Statistics &
    statistics() const;

  private:
    /** The original, homogenized and projected problems (original = problem without the
     *  projector). */
    void
    build_problems();
    /** The kind of a row of λ: 0 gluing and Dirichlet, 1 normal, 2 tangential. */
    unsigned int
    tier(const unsigned int row) const;
    /**
     * A solution of Gλ = @p e from the rows of the lowest tiers that restrain the floating
     * subdomains (CoarseProblem::particular_solution; for λ₀, see there).
     */
    DualVector
    particular_solution(const dealii::Vector<double> &e) const;
    /** The bounds λ̃_N ≥ −λ₀_N and the discs centred at −λ₀_T (radii 0). */
    void
    build_constraint_sets();
    /** ‖F‖ or ‖PFP‖, ρ, the bound of the Hessian's norm and the arc scale. */
    void
    estimate_scales(std::ostream &out);
    /** v ← P v = v − G̃ᵀG̃ v. */
    void
    apply_P(DualVector &v) const;
    /** MPGP's data from the parameters with ᾱ = 1.9/‖Hessian‖ and the arc scale. */
    QP::MPGP<DualVector>::AdditionalData
    mpgp_data() const;
    /** SMALBE's inner solver: MPGP over the whole set. */
    QP::SMALBE<DualVector>::InnerReport
    mpgp_inner_solve(const QP::Operator<DualVector> &A,
                     const DualVector               &b,
                     DualVector                     &x,
                     const double                    tolerance,
                     const DualVector               &gradient);
    /** The block Gauss–Seidel inner solver (Algorithms 1 and 2). */
    QP::SolverReport
    gauss_seidel(const QP::Operator<DualVector> &A,
                 const DualVector               &b,
                 DualVector                     &lambda,
                 const double                    tolerance,
                 const MovingSet                *moving_set);
    /** One block of a sweep: MPGP on the rows of @p block with the other rows fixed. */
    QP::MPGP<DualVector>::Statistics
    solve_block(const QP::Operator<DualVector> &A,
                const DualVector               &b,
                DualVector                     &lambda,
                const LocalDualRows::Block     &block,
                const QP::SeparableSet         &block_set,
                const double                    tolerance,
                unsigned int                   &counter);

    const DualProblem               &dual;
    const DualLayout                &layout;
    const std::vector<ContactNode>  &nodes;
    const Parameters::ContactSolver &parameters;
    /** The rows this rank holds. */
    LocalDualRows rows;
    /** The rows of λ_T = [0, n_T) and of λ_c = [λ_N; λ_E] = [n_T, m). */
    LocalDualRows::Block block_t, block_c;
    /**
     * Per contact node: the local indices of its normal row and of its first tangential row
     * (invalid without one).
     */
    std::vector<unsigned int> local_normal_row, local_tangential_row;
    /** h on this rank's rows. */
    DualVector       h;
    QP::SeparableSet set;   ///< Ω for all of λ̃
    QP::SeparableSet set_c; ///< bounds and free part, λ_c = [λ_N; λ_E]
    QP::SeparableSet set_t; ///< tangential part λ_T
    /** The disc of every contact node in set and set_t. */
    std::vector<unsigned int> disc_of_node;
    std::vector<double>       slip_bound;
    /** Whether SMALBE uses the projector variant (then λ₀ ≠ 0 and e = 0). */
    bool projector = false;
    /**
     * The dual problem min ½λᵀFλ − λᵀh over Ω with Gλ = e (`unscaled`), with orthonormalized
     * equality constraints G̃λ = ẽ (`original`); with the projector, its homogenization in
     * λ̃ = λ − λ₀ and the projected problem (PFP, Ph) that SMALBE solves (`problem`; without the
     * projector `problem` = `original`).
     */
    QP::Problem<DualVector>                             unscaled, original, homogeneous, problem;
    std::optional<QP::Orthonormalization<DualVector>>   orthonormalization;
    std::optional<QP::Homogenization<DualVector>>       homogenization;
    std::optional<QP::ProjectorEnforcement<DualVector>> projector_enforcement;
    /** λ₀ (zero without the projector). */
    DualVector lambda0;
    /** ‖G̃‖ (1, or 0 without rigid modes) and the penalty ρ. */
    double G_norm = 0, rho = 0;
    /**
     * The norm of the FETI part of the Hessian that ρ and the bound of the Hessian's norm are
     * taken from, and that SMALBE gets as QP::SMALBEParameters::F_norm: ‖PFP‖ (mpgp with
     * the projector) or ‖F‖, from projected_norm_iterations multiplications by F (in
     * F_applications, not in n_A).
     */
    double                        feti_norm                 = 0;
    static constexpr unsigned int projected_norm_iterations = 10;
    /**
     * The bound of the Hessian's norm behind the fixed step ᾱ = 1.9/‖A‖ of MPGP: ‖F‖ + ρ‖G̃‖²,
     * or max(‖F‖, ρ) for the projector variant (SMALBE/Hessian norm bound = max).
     */
    double hessian_norm = 0;
    /**
     * QP::MPGPParameters::arc_scale: 0 (the norm bound), or with Arc preconditioner
     * scale = mean diagonal the estimate of tr(A)/m of the Hessian, from arc_scale_probes
     * multiplications by F (in F_applications, not in n_A).
     */
    double                        arc_scale        = 0;
    static constexpr unsigned int arc_scale_probes = 10;
    Statistics                    counts;
  };
} // namespace FetiContact
