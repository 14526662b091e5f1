#pragma once

#include <deal.II/base/parameter_handler.h>

#include <feticontact/qp/mpgp.h>
#include <feticontact/qp/smalbe.h>

#include <string>

namespace FetiContact::Parameters
{
  /**
   * `subsection Contact solver`: how the contact problem with friction is solved. Frictionless
   * zones (μ = 0) need no tangential multipliers; with Coulomb friction the slip bound g = μ λ_N
   * is found by the method of successive approximations (MSA). The entries a user decides (law,
   * algorithm, accuracy, limits) are in the subsection itself; the switches of MSA in
   * `subsection Expert`, those of the QP solvers in `subsection MPGP` and `subsection SMALBE`
   * (QP::MPGPParameters, QP::SMALBEParameters). Their 'auto' values resolve by the
   * algorithm: the best measured configuration for mpgp (the default), the published one for
   * the paper's algorithms. The in-class defaults are those of the declared defaults
   * (Algorithm = mpgp, every 'auto').
   */
  struct ContactSolver
  {
    /** The friction law of the zones with μ > 0. */
    enum class FrictionLaw
    {
      coulomb, ///< g = μ λ_N, the fixed point found by MSA
      tresca   ///< given slip bound g (one value for every contact node)
    };
    FrictionLaw friction_law = FrictionLaw::coulomb;
    /** Tresca: the slip bound per contact node (N: λ are nodal forces). */
    double slip_bound = 0;

    enum class Algorithm
    {
      algorithm_1, ///< MSA outer loop, SMALBE with block Gauss–Seidel (MPRGP on λ_c, KPG on λ_t)
      algorithm_2, ///< MSA and the augmented Lagrangian merged in one loop (the paper's)
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
    /** Gauss–Seidel sweeps over (λ_c, λ_t) per inner problem (Algorithm 1). */
    unsigned int gauss_seidel_sweeps = 1;
    /** Relaxation ω of the slip-bound update g ← (1 − ω) g + ω μ λ_N. */
    double relaxation = 1;
    /** Continuation in the friction coefficients: stages μ/n, 2μ/n, …, μ (1: none). */
    unsigned int continuation_steps = 1;

    /**
     * `subsection MPGP`: the inner QP solver (its 'auto' entries resolved by the algorithm;
     * tolerance, step and arc scale are set per solve by the contact solver).
     */
    QP::MPGPParameters mpgp;
    /**
     * `subsection SMALBE`: the augmented Lagrangian. penalty_factor multiplies ‖PFP‖ (mpgp with
     * the projector: penalty_projected_norm) or ‖F‖; its 'auto' is resolved by the algorithm.
     */
    QP::SMALBEParameters smalbe;
    /**
     * The norm that the penalty factor multiplies and that bounds the FETI part of the Hessian
     * in MPGP's step: true ‖PFP‖ (mpgp with the projector), false ‖F‖ (the paper's algorithms,
     * the polygonal baseline and the penalty variant).
     */
    bool penalty_projected_norm = true;

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
    /** `subsection MPGP` and `subsection SMALBE`, with their 'auto' values for the algorithm. */
    void
    parse_qp_parameters(dealii::ParameterHandler &prm);
  };
} // namespace FetiContact::Parameters
