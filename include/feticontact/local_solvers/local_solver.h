#pragma once

#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <memory>
#include <string>

namespace FetiContact
{
  /**
   * A sparse direct solver for one symmetric positive definite matrix: the regularized stiffness
   * matrix of a subdomain (whose solves give the generalized inverse K⁺) or the coarse matrix
   * GGᵀ. Backends: CHOLMOD, Amesos2 KLU2, Amesos MUMPS, UMFPACK. Each object owns one
   * factorization; solves may be called many times.
   */
  class LocalSolver
  {
  public:
    virtual ~LocalSolver() = default;

    /** Analyses and factorizes @p A (full symmetric pattern stored). */
    virtual void
    factorize(const dealii::SparseMatrix<double> &A) = 0;

    /** Overwrites @p x = A⁻¹ x. */
    virtual void
    solve(dealii::Vector<double> &x) const = 0;

    /**
     * Whether objects of this backend may factorize and solve on several threads at once, each
     * object on one thread (no state shared between the objects).
     */
    virtual bool
    thread_safe() const
    {
      return false;
    }

    /** The backend's name as in the parameter file. */
    virtual std::string
    name() const = 0;

    /** Creates the backend named @p name ('cholmod', 'amesos2-klu2', …). */
    static std::unique_ptr<LocalSolver>
    create(const std::string &name);

    /** The names accepted by create(), '|'-separated for Patterns::Selection. */
    static std::string
    available_backends();
  };
} // namespace FetiContact
