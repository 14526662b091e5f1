#pragma once

#include <feticontact/local_solvers/local_solver.h>

#include <cholmod.h>

namespace FetiContact
{
  /**
   * SuiteSparse CHOLMOD, supernodal Cholesky LLᵀ with CHOLMOD's choice of fill-reducing ordering
   * (AMD or METIS). The fastest backend measured here (doc/local_solvers.md) and the default.
   */
  class CholmodSolver : public LocalSolver
  {
  public:
    CholmodSolver();
    ~CholmodSolver() override;

    void
    factorize(const dealii::SparseMatrix<double> &A) override;
    void
    solve(dealii::Vector<double> &x) const override;
    std::string
    name() const override
    {
      return "cholmod";
    }

    /**
     * With the factorization P A Pᵀ = L Lᵀ (P the fill-reducing permutation): x ← L⁻¹ P x if
     * @p transpose is false, x ← Pᵀ L⁻ᵀ x if true. Then A⁻¹ = (L⁻¹P)ᵀ(L⁻¹P), and for A = GGᵀ the
     * rows of L⁻¹PG are orthonormal.
     */
    void
    solve_half(dealii::Vector<double> &x, const bool transpose) const;

    /**
     * An estimate of the reciprocal condition number from the diagonal of L (cholmod_rcond);
     * used to detect a singular coarse matrix GGᵀ.
     */
    double
    reciprocal_condition_estimate() const;

  private:
    mutable cholmod_common common;
    cholmod_factor        *factor = nullptr;
    mutable cholmod_dense *x_work = nullptr, *y_work = nullptr, *e_work = nullptr;
    mutable cholmod_dense *b_work = nullptr;
    std::size_t            n      = 0;
  };
} // namespace FetiContact
