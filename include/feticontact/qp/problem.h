#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/qp/separable_set.h>

#include <functional>

namespace FetiContact::QP
{
  /** A symmetric linear operator given by its action y = A x. */
  template <typename VectorType>
  using Operator = std::function<void(const VectorType &, VectorType &)>;

  /**
   * @brief A quadratic program with separable constraints and linear equality constraints,
   *
   *     min ½λᵀFλ − λᵀh   s.t.  λ ∈ Ω,  Gλ = e,
   *
   * given by operators and vectors only (the QP layer knows nothing of meshes). Transforms
   * (Homogenization, ProjectorEnforcement) make a new Problem from one and own the step back to
   * the solution of the original.
   *
   * λ and h are of @p VectorType (DistributedVector, deal.II's distributed vector, with the
   * entries spread over the ranks); the constraint side, e and the multipliers of Gλ = e, is small
   * (one number per rigid body mode) and held whole by every rank as a dealii::Vector<double>: G
   * maps a VectorType to it, Gᵀ back.
   */
  template <typename VectorType>
  struct Problem
  {
    /** F, symmetric positive semidefinite. */
    Operator<VectorType> hessian;
    /** h. */
    VectorType linear_term;
    /** Ω (not owned; the caller may change its radii and bounds between solves). */
    const SeparableSet *set = nullptr;
    /** G: R^m → R^k and Gᵀ (empty when k = 0). */
    std::function<void(const VectorType &, dealii::Vector<double> &)> G;
    std::function<void(const dealii::Vector<double> &, VectorType &)> Gt;
    /** e ∈ R^k. */
    dealii::Vector<double> e;
    /**
     * Optional: y = (F + ρGᵀG) x in one pass, for a transform whose F already applies GᵀG
     * (ProjectorEnforcement shares the product Qx = GᵀGx between PFP and ρQ). Empty: F, then
     * GᵀG.
     */
    std::function<void(double, const VectorType &, VectorType &)> augmented_hessian;

    /**
     * The scale of the linear term that relative stopping tests refer to; 0: ‖h‖. A transform
     * that removes part of h keeps the scale of the problem it came from (ProjectorEnforcement:
     * ‖h‖, not ‖Ph‖, so that a tolerance means the same with or without the projector).
     */
    double linear_term_scale = 0;

    /** The scale of the linear term: linear_term_scale, or ‖h‖. */
    double
    linear_term_norm() const
    {
      return linear_term_scale > 0 ? linear_term_scale : l2_norm(linear_term);
    }

    /** m, the number of unknowns (over all ranks). */
    unsigned int
    size() const
    {
      return linear_term.size();
    }
  };
} // namespace FetiContact::QP
