#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/qp/problem.h>

namespace FetiContact::QP
{
  /**
   * @brief Orthonormalization of the equality constraints: Gλ = e ⟺ G̃λ = ẽ with G̃G̃ᵀ = I.
   *
   * With a factorization of GGᵀ (on the range of G; in FETI the coarse problem's, which knows
   * the sparsity and the rank of GGᵀ) given as the in-place maps v ← L⁻¹v and v ← L⁻ᵀv:
   * G̃ = L⁻¹G, G̃ᵀ = GᵀL⁻ᵀ, ẽ = L⁻¹e. With orthonormal rows, ‖G̃‖ = 1 and the penalty ρ of SMALBE
   * and the projector P = I − G̃ᵀG̃ need no scaling. recover_multiplier() is the step back for
   * the multiplier: ν = L⁻ᵀν̃ satisfies Gᵀν = G̃ᵀν̃.
   */
  template <typename VectorType>
  class Orthonormalization
  {
  public:
    /** The factor L of GGᵀ = LLᵀ, applied as solves in place. */
    struct Factor
    {
      std::function<void(dealii::Vector<double> &)> solve_L, solve_Lt;
    };

    Orthonormalization(const Problem<VectorType> &original, const Factor &factor);
    /** The transform refers to the original problem: no temporaries. */
    Orthonormalization(Problem<VectorType> &&, const Factor &) = delete;

    /** The problem with G̃ and ẽ. */
    Problem<VectorType>
    transformed() const;

    /** ν = L⁻ᵀν̃, the multiplier of Gλ = e from that of G̃λ = ẽ. */
    dealii::Vector<double>
    recover_multiplier(const dealii::Vector<double> &nu_tilde) const;

  private:
    const Problem<VectorType> &original;
    Factor                     factor;
  };

  /**
   * @brief Homogenization of the equality constraint: λ = λ₀ + λ̃ with Gλ₀ = e.
   *
   * The transformed problem in λ̃ has the linear term h − Fλ₀ and e = 0, and the set Ω − λ₀.
   * The set is the caller's to build in the shifted coordinates (bounds −λ₀_i, discs centred
   * at −λ₀), since the caller also changes its radii between solves. recover() is the step
   * back, λ = λ̃ + λ₀.
   */
  template <typename VectorType>
  class Homogenization
  {
  public:
    /** @p particular_solution is λ₀, any solution of Gλ₀ = e (e.g. of least norm). */
    Homogenization(const Problem<VectorType> &original, const VectorType &particular_solution);
    /** The transform refers to the original problem: no temporaries. */
    Homogenization(Problem<VectorType> &&, const VectorType &) = delete;

    /** The problem in λ̃ over @p shifted_set = Ω − λ₀. One multiplication by F (for Fλ₀). */
    Problem<VectorType>
    transformed(const SeparableSet &shifted_set) const;

    /** λ̃ → λ = λ̃ + λ₀, in place. */
    void
    recover(VectorType &lambda) const;

    /** λ₀. */
    const VectorType &
    particular_solution() const;

  private:
    const Problem<VectorType> &original;
    VectorType                 lambda0;
  };

  /**
   * @brief Enforcement of a homogeneous equality constraint Gλ = 0 by the projector
   * P = I − GᵀG (Farhat–Mandel–Roux; Dostál's TFETI contact solvers).
   *
   * For G with orthonormal rows (GGᵀ = I, so Q = GᵀG and P = I − Q are orthogonal projectors),
   * the transformed problem minimizes ½λᵀPFPλ − λᵀPh, which agrees with the original objective
   * on Gλ = 0. SMALBE's augmented Lagrangian then has the Hessian PFP + ρQ: on the range of P the
   * spectrum of the projected FETI operator (the natural coarse space), on that of Q the penalty
   * ρ, so both the inner iterations and the multiplier iterations need fewer steps than with
   * F + ρGᵀG. Problem::augmented_hessian applies PFP + ρQ with one product Qx.
   * recover_multiplier() is the step back for the multiplier of Gλ = 0: the ν of the
   * transformed problem is not that of the original one.
   */
  template <typename VectorType>
  class ProjectorEnforcement
  {
  public:
    /** Requires e = 0 (apply Homogenization first) and G with orthonormal rows. */
    explicit ProjectorEnforcement(const Problem<VectorType> &homogeneous);
    /** The transform refers to the homogeneous problem: no temporaries. */
    explicit ProjectorEnforcement(Problem<VectorType> &&) = delete;

    /** The problem with F → PFP and h → Ph. */
    Problem<VectorType>
    transformed() const;

    /**
     * ν of the original problem from that of the transformed one: ν ← ν − G r, with
     * r = Fλ − h the gradient of the original objective at the solution.
     */
    void
    recover_multiplier(const VectorType &r, dealii::Vector<double> &nu) const;

    /** y = P x = x − GᵀG x. */
    void
    project(const VectorType &x, VectorType &y) const;

  private:
    const Problem<VectorType> &homogeneous;
    VectorType                 projected_linear_term;
  };
} // namespace FetiContact::QP
