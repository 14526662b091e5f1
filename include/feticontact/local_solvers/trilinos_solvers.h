#pragma once

#include <feticontact/local_solvers/local_solver.h>

#include <memory>

class Epetra_CrsMatrix;
class Epetra_Map;
class Epetra_MpiComm;

namespace FetiContact
{
  /**
   * Shared part of the Trilinos backends: the matrix copied into an Epetra_CrsMatrix on
   * MPI_COMM_SELF (a subdomain lives on one rank).
   */
  class EpetraLocalMatrix
  {
  public:
    EpetraLocalMatrix();
    ~EpetraLocalMatrix();
    /** Copies @p A. */
    void
    set(const dealii::SparseMatrix<double> &A);

  protected:
    std::unique_ptr<Epetra_MpiComm>   comm;
    std::unique_ptr<Epetra_Map>       map;
    std::shared_ptr<Epetra_CrsMatrix> matrix;
  };

  /**
   * Trilinos Amesos2 with KLU2 (sparse LU). The design card's backend; about 40× slower than
   * CHOLMOD on elasticity blocks here (doc/local_solvers.md), kept for comparison and for
   * machines without SuiteSparse. KLU2 does not detect singular matrices: the FETI layer hands
   * it regularized (nonsingular) matrices only.
   */
  class Amesos2Klu2Solver : public LocalSolver, private EpetraLocalMatrix
  {
  public:
    Amesos2Klu2Solver();
    ~Amesos2Klu2Solver() override;
    void
    factorize(const dealii::SparseMatrix<double> &A) override;
    void
    solve(dealii::Vector<double> &x) const override;
    std::string
    name() const override
    {
      return "amesos2-klu2";
    }

  private:
    struct Data;
    std::unique_ptr<Data> data;
  };

  /** Trilinos Amesos (version 1) with MUMPS (multifrontal LU, sequential on MPI_COMM_SELF). */
  class AmesosMumpsSolver : public LocalSolver, private EpetraLocalMatrix
  {
  public:
    AmesosMumpsSolver();
    ~AmesosMumpsSolver() override;
    void
    factorize(const dealii::SparseMatrix<double> &A) override;
    void
    solve(dealii::Vector<double> &x) const override;
    std::string
    name() const override
    {
      return "amesos-mumps";
    }

  private:
    struct Data;
    std::unique_ptr<Data> data;
  };
} // namespace FetiContact
