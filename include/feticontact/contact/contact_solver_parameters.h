#pragma once

#include <deal.II/base/parameter_handler.h>

#include <feticontact/qp/mpgp.h>

#include <string>

namespace FetiContact::Parameters
{
  /**
   * `subsection Contact solver`: how the contact problem with friction is solved. Frictionless
   * zones (F = 0) need no tangential multipliers; with Coulomb friction the slip bound g = F λ_N
   * is found by the method of successive approximations (MSA). The entries a user decides (law,
   * algorithm, accuracy, limits) are in the subsection itself; the research switches of the
   * solvers in `subsection Expert`, whose 'auto' values resolve by the algorithm: the best
   * measured configuration for mpgp (the default), the published one for the seed's algorithms.
   * The in-class defaults are those of the declared defaults (Algorithm = mpgp, every Expert
   * entry 'auto').
   */
  struct ContactSolver
  {
    /** The friction law of the zones with F > 0. */
    enum class FrictionLaw
    {
      coulomb, ///< g = F λ_N, the fixed point found by MSA
      tresca   ///< given slip bound g (one value for every contact node)
    };
    FrictionLaw friction_law = FrictionLaw::coulomb;
    /** Tresca: the slip bound per contact node (N: λ are nodal forces). */
    double slip_bound = 0;

    enum class Algorithm
    {
      algorithm_1, ///< MSA outer loop, SMALBE with block Gauss–Seidel (MPRGP on λ_c, KPG on λ_t)
      algorithm_2, ///< MSA and the augmented Lagrangian merged in one loop (the seed's)
      mpgp,        ///< MSA outer loop, SMALBE with one MPGP over bounds × discs
      polygonal    ///< MSA outer loop, the disc replaced by a 2s-gon: bounds only (MPRGP)
    };
    Algorithm algorithm = Algorithm::mpgp;
    /** Polygonal baseline: s tangential multipliers per node (a regular 2s-gon). */
    unsigned int polygon_directions = 4;

    /** SMALBE stops when ‖g^P‖ ≤ tol ‖h‖ and ‖Gλ − e‖ ≤ tol ‖e‖. */
    double qp_tolerance = 1e-8;
    /** MSA stops when ‖g_new − g‖ ≤ tol ‖g_new‖ (relative change of the slip bound). */
    double       msa_tolerance      = 1e-6;
    unsigned int max_msa_iterations = 100;
    /**
     * Inexact MSA: MSA step j solves its Tresca problem to max(qp_tolerance, c · change_{j−1})
     * (change_0 = 1); 0: every step to qp_tolerance.
     */
    double inexact_msa_factor = 1e-3;
    /** QP::SMALBE::AdditionalData::inner_floor. */
    double inner_tolerance_floor = 1;
    /** SMALBE outer iterations per QP solve ("auto": 200 for algorithm 2, 2000 otherwise). */
    unsigned int max_smalbe_iterations = 2000;
    unsigned int max_inner_iterations  = 10000;
    /** Gauss–Seidel sweeps over (λ_c, λ_t) per inner problem (Algorithm 1). */
    unsigned int gauss_seidel_sweeps = 1;
    /** Relaxation ω of the slip-bound update g ← (1 − ω) g + ω F λ_N. */
    double relaxation = 1;
    /** Continuation in F: stages F/n, 2F/n, …, F (1: none). */
    unsigned int continuation_steps = 1;
    /** SMALBE penalty ρ as a multiple of ‖F‖, or of ‖PFP‖ with penalty_projected_norm. */
    double penalty_factor = 5;
    /** s of SMALBE's multiplier update μ ← μ + sρ(Gλ − e) (QP::SMALBE::AdditionalData). */
    double multiplier_step = 1;
    /**
     * The norm that penalty_factor multiplies and that bounds the FETI part of the Hessian in
     * MPGP's step: true ‖PFP‖ (mpgp with the projector), false ‖F‖ (the seed's algorithms, the
     * polygonal baseline and the penalty variant).
     */
    bool penalty_projected_norm = true;

    /** How SMALBE treats Gλ = e (QP::ProjectorEnforcement). */
    enum class EqualityConstraint
    {
      projector, ///< λ = λ₀ + λ̃ with Gλ₀ = e; Hessian PFP + ρQ (Farhat–Mandel–Roux)
      penalty    ///< the Hessian F + ρG̃ᵀG̃ (SMALBE on the original problem)
    };
    EqualityConstraint equality_constraint = EqualityConstraint::projector;
    /** MPGP/KPG: conjugate gradient steps along the circles of active discs. */
    bool disc_rotations = true;
    /** MPGP's expansion step ("Expansion step": fixed or projected cg). */
    QP::MPGP::AdditionalData::Expansion expansion =
      QP::MPGP::AdditionalData::Expansion::projected_cg;
    /**
     * The bound of ‖A‖ for MPGP's fixed step: false ‖F‖ + ρ; true max(‖F‖, ρ), exact for the
     * projector variant (PFP and ρQ act on complementary orthogonal subspaces).
     */
    bool hessian_norm_max = true;
    /** QP::MPGP::AdditionalData::recursive_gradient_tolerance ("Recursive gradient tolerance"; 0:
     * recompute). */
    double recursive_gradient_tolerance = 0.1;
    /**
     * The scale of the Hessian in the preconditioner of MPGP's steps along the circles
     * ("Arc preconditioner scale"): false its norm bound, true its mean diagonal
     * (QP::MPGP::AdditionalData::arc_scale).
     */
    bool arc_scale_mean_diagonal = true;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);

  private:
    /** `subsection Contact solver / Expert`, entered. */
    static void
    declare_expert_parameters(dealii::ParameterHandler &prm);
    /** The same; after the algorithm is known ('auto' values depend on it). */
    void
    parse_expert_parameters(dealii::ParameterHandler &prm);
  };
} // namespace FetiContact::Parameters
