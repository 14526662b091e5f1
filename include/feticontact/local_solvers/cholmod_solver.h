#pragma once

#include <feticontact/local_solvers/local_solver.h>

#include <cholmod.h>

namespace FetiContact
{
  /**
   * The upper triangle of the symmetric matrix @p A in CHOLMOD's compressed-column form (stype 1,
   * rows sorted), allocated in @p common: with Int = int for the cholmod_* routines (the local
   * solver), with Int = SuiteSparse_long for the 64-bit cholmod_l_* routines (a factor of more
   * than 2³¹ entries, as of the undecomposed brick at 10⁶ unknowns in
   * benchmarks/monolithic_solve.cc). The caller frees it.
   */
  template <typename Int>
  cholmod_sparse *
  upper_triangle(const dealii::SparseMatrix<double> &A, cholmod_common &common);

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
