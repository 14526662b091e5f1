#include <feticontact/base/input_parsing.h>
#include <feticontact/local_solvers/trilinos_solvers.h>

#include <Amesos.h>
#include <Amesos2.hpp>
#include <Epetra_CrsMatrix.h>
#include <Epetra_LinearProblem.h>
#include <Epetra_Map.h>
#include <Epetra_MpiComm.h>
#include <Epetra_MultiVector.h>
#include <Teuchos_RCP.hpp>

#include <vector>

namespace FetiContact
{
  using namespace dealii;

  EpetraLocalMatrix::EpetraLocalMatrix()
    : comm(std::make_unique<Epetra_MpiComm>(MPI_COMM_SELF))
  {}

  EpetraLocalMatrix::~EpetraLocalMatrix() = default;

  void
  EpetraLocalMatrix::set(const SparseMatrix<double> &A)
  {
    const int n = A.m();
    map         = std::make_unique<Epetra_Map>(n, 0, *comm);
    std::vector<int> entries_per_row(n);
    for (int i = 0; i < n; ++i)
      entries_per_row[i] = A.get_row_length(i);
    matrix = std::make_shared<Epetra_CrsMatrix>(Copy, *map, entries_per_row.data(), true);
    std::vector<int>    columns;
    std::vector<double> values;
    for (int i = 0; i < n; ++i)
      {
        columns.clear();
        values.clear();
        for (auto it = A.begin(i); it != A.end(i); ++it)
          {
            columns.push_back(it->column());
            values.push_back(it->value());
          }
        matrix->InsertGlobalValues(i, columns.size(), values.data(), columns.data());
      }
    matrix->FillComplete();
  }

  struct Amesos2Klu2Solver::Data
  {
    Teuchos::RCP<Amesos2::Solver<Epetra_CrsMatrix, Epetra_MultiVector>> solver;
  };

  Amesos2Klu2Solver::Amesos2Klu2Solver()
    : data(std::make_unique<Data>())
  {}

  Amesos2Klu2Solver::~Amesos2Klu2Solver() = default;

  void
  Amesos2Klu2Solver::factorize(const SparseMatrix<double> &A)
  {
    set(A);
    const Teuchos::RCP<const Epetra_CrsMatrix> rcp_matrix = Teuchos::rcp(matrix.get(), false);
    data->solver = Amesos2::create<Epetra_CrsMatrix, Epetra_MultiVector>("KLU2", rcp_matrix);
    data->solver->symbolicFactorization();
    data->solver->numericFactorization();
  }

  void
  Amesos2Klu2Solver::solve(Vector<double> &x) const
  {
    if (x.size() == 0)
      return;
    Epetra_MultiVector b(View, *map, x.begin(), x.size(), 1);
    Epetra_MultiVector y(*map, 1);
    data->solver->solve(Teuchos::ptr(&y), Teuchos::ptr(&b));
    for (unsigned int i = 0; i < x.size(); ++i)
      x[i] = y[0][i];
  }

  struct AmesosMumpsSolver::Data
  {
    Epetra_LinearProblem                problem;
    std::unique_ptr<Amesos_BaseSolver>  solver;
    std::unique_ptr<Epetra_MultiVector> lhs, rhs;
  };

  AmesosMumpsSolver::AmesosMumpsSolver()
    : data(std::make_unique<Data>())
  {}

  AmesosMumpsSolver::~AmesosMumpsSolver() = default;

  void
  AmesosMumpsSolver::factorize(const SparseMatrix<double> &A)
  {
    set(A);
    data->lhs = std::make_unique<Epetra_MultiVector>(*map, 1);
    data->rhs = std::make_unique<Epetra_MultiVector>(*map, 1);
    data->problem.SetOperator(matrix.get());
    data->problem.SetLHS(data->lhs.get());
    data->problem.SetRHS(data->rhs.get());
    Amesos factory;
    data->solver.reset(factory.Create("Amesos_Mumps", data->problem));
    require(data->solver != nullptr, "Amesos was built without MUMPS.");
    Teuchos::ParameterList list;
    list.set("MatrixProperty", "SPD");
    data->solver->SetParameters(list);
    require(data->solver->SymbolicFactorization() == 0 && data->solver->NumericFactorization() == 0,
            "Amesos MUMPS: the factorization failed.");
  }

  void
  AmesosMumpsSolver::solve(Vector<double> &x) const
  {
    if (x.size() == 0)
      return;
    for (unsigned int i = 0; i < x.size(); ++i)
      (*data->rhs)[0][i] = x[i];
    data->solver->Solve();
    for (unsigned int i = 0; i < x.size(); ++i)
      x[i] = (*data->lhs)[0][i];
  }
} // namespace FetiContact
