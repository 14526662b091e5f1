#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/vector.h>

#include <functional>

namespace FetiContact::QP
{
  /** What a QP solver reports. */
  struct SolverReport
  {
    unsigned int iterations              = 0;
    unsigned int hessian_multiplications = 0;
    bool         converged               = false;
    /** ‖projected gradient‖ / reference at the end. */
    double relative_residual = 0;
    /**
     * Whether the solver stopped because its residual stagnated above the tolerance (the
     * rounding of the operator bounds the attainable accuracy; ProjectedCG), not at its limit.
     */
    bool stagnated = false;
  };

  /** The parameters of projected CG (ProjectedCG::AdditionalData). */
  struct ProjectedCGParameters
  {
    /** The relative tolerance: ‖P(Ax − b)‖ ≤ tolerance · ‖Pb‖ (see the class). */
    double tolerance = 1e-10;
    /** The largest number of iterations. */
    unsigned int max_iterations = 5000;

    /**
     * Declares, in the current subsection of @p prm, Relative tolerance and Maximum
     * iterations.
     */
    static void
    declare_parameters(dealii::ParameterHandler &prm);

    /** Reads the entries of declare_parameters(). */
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /**
   * Conjugate gradients for min ½ xᵀA x − xᵀb subject to x ∈ x₀ + range(P), where P is an
   * orthogonal projector (in FETI: P = I − Gᵀ(GGᵀ)⁻¹G and x₀ with Gx₀ = e). Stops when
   * ‖P(Ax − b)‖ ≤ tolerance · max(‖P b‖, 64 ε (‖b‖ + ‖Ax₀‖) / tolerance): relative to the
   * projected right-hand side, but never below the rounding level of the data (ε the machine
   * epsilon), so that a problem whose x₀ already solves it stops at once instead of iterating
   * on noise.
   *
   * Stagnation: when the least ‖P(Ax − b)‖ has not halved for max(100, k/4) iterations (k the
   * iterations so far), the residual has reached the floor that the rounding of A x leaves
   * (with an ill-conditioned A, e.g. the subdomain matrices of a thin plate, above the
   * tolerance): the solver recomputes P(Ax − b) from x once and stops, converged if that meets
   * the tolerance, else with SolverReport::stagnated, instead of iterating on at the floor until
   * max_iterations. Knows nothing of meshes: A and P are functions; instantiated for
   * DistributedVector.
   *
   * An object with its AdditionalData (declared in the caller's prm subsection) whose solve()
   * returns its statistics (a SolverReport).
   */
  template <typename VectorType>
  class ProjectedCG
  {
  public:
    using AdditionalData = ProjectedCGParameters;

    /** A symmetric operator y = A x, and the projector applied in place, x ← P x. */
    using Operator  = std::function<void(const VectorType &, VectorType &)>;
    using Projector = std::function<void(VectorType &)>;

    /** With the default AdditionalData. */
    ProjectedCG();

    explicit ProjectedCG(const AdditionalData &data);

    /**
     * Solves the problem.
     *
     * @param x  in: x₀ (feasible); out: the solution.
     * @param monitor called after every iteration with (iteration, relative residual).
     * @param M a symmetric positive (semi)definite preconditioner, applied as P M P (Farhat–
     *          Mandel–Roux); empty: none. The stopping test stays on the unpreconditioned
     *          ‖P(Ax − b)‖.
     */
    SolverReport
    solve(const Operator                                  &A,
          const Projector                                 &P,
          const VectorType                                &b,
          VectorType                                      &x,
          const std::function<void(unsigned int, double)> &monitor = {},
          const Operator                                  &M       = {}) const;

  private:
    AdditionalData additional_data;
  };
} // namespace FetiContact::QP
