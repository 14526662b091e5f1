#pragma once

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
  };

  /**
   * Conjugate gradients for min ½ xᵀA x − xᵀb subject to x ∈ x₀ + range(P), where P is an
   * orthogonal projector (in FETI: P = I − Gᵀ(GGᵀ)⁻¹G and x₀ with Gx₀ = e). Stops when
   * ‖P(Ax − b)‖ ≤ tolerance · max(‖P b‖, 64 ε (‖b‖ + ‖Ax₀‖) / tolerance): relative to the
   * projected right-hand side, but never below the rounding level of the data (ε the machine
   * epsilon), so that a problem whose x₀ already solves it stops at once instead of iterating
   * on noise. Knows nothing of meshes: A and P are functions.
   *
   * @param x  in: x₀ (feasible); out: the solution.
   * @param monitor called after every iteration with (iteration, relative residual).
   * @param M a symmetric positive (semi)definite preconditioner, applied as P M P (Farhat–Mandel–
   *          Roux); empty: none. The stopping test stays on the unpreconditioned ‖P(Ax − b)‖.
   */
  SolverReport
  projected_conjugate_gradient(
    const std::function<void(const dealii::Vector<double> &, dealii::Vector<double> &)> &A,
    const std::function<void(dealii::Vector<double> &)>                                 &P,
    const dealii::Vector<double>                                                        &b,
    dealii::Vector<double>                                                              &x,
    const double                                                                         tolerance,
    const unsigned int                               max_iterations,
    const std::function<void(unsigned int, double)> &monitor                               = {},
    const std::function<void(const dealii::Vector<double> &, dealii::Vector<double> &)> &M = {});
} // namespace FetiContact::QP
