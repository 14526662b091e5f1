#include <deal.II/lac/sparse_direct.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/local_solvers/cholmod_solver.h>
#include <feticontact/local_solvers/local_solver.h>
#include <feticontact/local_solvers/trilinos_solvers.h>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    /** SuiteSparse UMFPACK (sparse LU) through deal.II's SparseDirectUMFPACK. */
    class UmfpackSolver : public LocalSolver
    {
    public:
      void
      factorize(const SparseMatrix<double> &A) override
      {
        solver.initialize(A);
      }
      void
      solve(Vector<double> &x) const override
      {
        if (x.size() > 0)
          const_cast<SparseDirectUMFPACK &>(solver).solve(x);
      }
      bool
      thread_safe() const override
      {
        return true;
      }
      std::string
      name() const override
      {
        return "umfpack";
      }

    private:
      SparseDirectUMFPACK solver;
    };
  } // namespace

  std::unique_ptr<LocalSolver>
  LocalSolver::create(const std::string &name)
  {
    if (name == "cholmod")
      return std::make_unique<CholmodSolver>(CholmodSolver::Solves::project);
    if (name == "cholmod-library-solves")
      return std::make_unique<CholmodSolver>(CholmodSolver::Solves::library);
    if (name == "amesos2-klu2")
      return std::make_unique<Amesos2Klu2Solver>();
    if (name == "amesos-mumps")
      return std::make_unique<AmesosMumpsSolver>();
    if (name == "umfpack")
      return std::make_unique<UmfpackSolver>();
    throw InputError("Unknown local solver <" + name + ">; available: " + available_backends());
  }

  std::string
  LocalSolver::available_backends()
  {
    return "cholmod|cholmod-library-solves|amesos2-klu2|amesos-mumps|umfpack";
  }
} // namespace FetiContact
