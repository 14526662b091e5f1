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
