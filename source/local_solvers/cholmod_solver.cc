#include <feticontact/base/input_parsing.h>
#include <feticontact/local_solvers/cholmod_solver.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace FetiContact
{
  using namespace dealii;

  template <typename Int>
  cholmod_sparse *
  upper_triangle(const SparseMatrix<double> &A, cholmod_common &common)
  {
    static_assert(std::is_same_v<Int, int> || std::is_same_v<Int, SuiteSparse_long>);
    const std::size_t n = A.m();
    // Column j of the upper triangle is row j of the lower triangle, and A is symmetric.
    std::size_t nnz = 0;
    for (std::size_t j = 0; j < n; ++j)
      for (auto it = A.begin(j); it != A.end(j); ++it)
        nnz += it->column() <= j;
    cholmod_sparse *S = std::is_same_v<Int, int> ?
                          cholmod_allocate_sparse(n, n, nnz, 1, 1, 1, CHOLMOD_REAL, &common) :
                          cholmod_l_allocate_sparse(n, n, nnz, 1, 1, 1, CHOLMOD_REAL, &common);
    require(S != nullptr,
            "CHOLMOD: no memory for a matrix of " + std::to_string(nnz) + " entries.");
    auto                               *p = static_cast<Int *>(S->p);
    auto                               *i = static_cast<Int *>(S->i);
    auto                               *x = static_cast<double *>(S->x);
    std::vector<std::pair<Int, double>> column;
    std::size_t                         k = 0;
    for (std::size_t j = 0; j < n; ++j)
      {
        p[j] = k;
        column.clear();
        for (auto it = A.begin(j); it != A.end(j); ++it)
          if (it->column() <= j)
            column.emplace_back(it->column(), it->value());
        std::sort(column.begin(), column.end());
        for (const auto &[row, value] : column)
          {
            i[k] = row;
            x[k] = value;
            ++k;
          }
      }
    p[n] = k;
    return S;
  }

  template cholmod_sparse *
  upper_triangle<int>(const SparseMatrix<double> &, cholmod_common &);
  template cholmod_sparse *
  upper_triangle<SuiteSparse_long>(const SparseMatrix<double> &, cholmod_common &);

  std::string
  cholmod_status_text(const int status)
  {
    switch (status)
      {
        case CHOLMOD_OK:
          return "ok";
        case CHOLMOD_NOT_POSDEF:
          return "the matrix is not positive definite";
        case CHOLMOD_DSMALL:
          return "a diagonal entry of the factor is tiny (nearly singular matrix)";
        case CHOLMOD_OUT_OF_MEMORY:
          return "out of memory";
        case CHOLMOD_TOO_LARGE:
          return "the factor is too large for CHOLMOD's integer type";
        case CHOLMOD_INVALID:
          return "invalid input";
        default:
          return "status " + std::to_string(status);
      }
  }

  LongCholmodStatistics
  solve_by_long_cholmod(const SparseMatrix<double> &K, Vector<double> &u)
  {
    using clock         = std::chrono::steady_clock;
    const std::size_t n = K.m();
    AssertThrow(u.size() == n, ExcDimensionMismatch(u.size(), n));
    LongCholmodStatistics statistics;
    if (n == 0)
      return statistics;
    cholmod_common common;
    cholmod_l_start(&common);
    common.supernodal        = CHOLMOD_SUPERNODAL;
    common.print             = 0;
    cholmod_sparse *S        = nullptr;
    cholmod_factor *factor   = nullptr;
    cholmod_dense  *b        = nullptr;
    cholmod_dense  *solution = nullptr;
    const auto      release  = [&]() {
      cholmod_l_free_dense(&solution, &common);
      cholmod_l_free_dense(&b, &common);
      cholmod_l_free_factor(&factor, &common);
      cholmod_l_free_sparse(&S, &common);
      cholmod_l_finish(&common);
    };
    // Throws unless CHOLMOD's last call succeeded and returned `result`.
    const auto check = [&](const void *result, const std::string &what) {
      if (result != nullptr && common.status == CHOLMOD_OK)
        return;
      const std::string message = "CHOLMOD (64-bit) failed in " + what + " of a matrix of " +
                                  std::to_string(n) +
                                  " rows: " + cholmod_status_text(common.status) + ".";
      release();
      throw std::runtime_error(message);
    };

    const auto t0 = clock::now();
    try
      {
        S = upper_triangle<SuiteSparse_long>(K, common);
      }
    catch (...)
      {
        release();
        throw;
      }
    factor = cholmod_l_analyze(S, &common);
    check(factor, "the analysis");
    cholmod_l_factorize(S, factor, &common);
    if (common.status != CHOLMOD_NOT_POSDEF && common.status != CHOLMOD_DSMALL)
      check(factor, "the factorization");
    if (common.status != CHOLMOD_OK || factor->minor != n)
      {
        const std::string minor = std::to_string(factor->minor);
        release();
        require(false,
                "CHOLMOD (64-bit): the matrix is not positive definite (leading minor " + minor +
                  " of " + std::to_string(n) + "): the body is not held as the scene claims.");
      }
    statistics.factor_entries = common.lnz;
    const auto t1             = clock::now();
    b                         = cholmod_l_allocate_dense(n, 1, n, CHOLMOD_REAL, &common);
    check(b, "allocating the right-hand side");
    std::copy(u.begin(), u.end(), static_cast<double *>(b->x));
    solution = cholmod_l_solve(CHOLMOD_A, factor, b, &common);
    check(solution, "the solve");
    std::copy_n(static_cast<const double *>(solution->x), n, u.begin());
    const auto t2                    = clock::now();
    statistics.factorization_seconds = std::chrono::duration<double>(t1 - t0).count();
    statistics.solve_seconds         = std::chrono::duration<double>(t2 - t1).count();
    release();
    return statistics;
  }

  CholmodSolver::CholmodSolver(const Solves solves)
    : solves(solves)
  {
    cholmod_start(&common);
    common.supernodal = CHOLMOD_SUPERNODAL;
    common.print      = 0;
  }

  CholmodSolver::~CholmodSolver()
  {
    for (cholmod_dense **d : {&x_work, &y_work, &e_work, &b_work})
      if (*d != nullptr)
        cholmod_free_dense(d, &common);
    if (factor != nullptr)
      cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }

  void
  CholmodSolver::factorize(const SparseMatrix<double> &A)
  {
    n                 = A.m();
    values_moved      = false;
    cholmod_sparse *S = upper_triangle<int>(A, common);
    supernodal.reset();
    if (factor != nullptr)
      cholmod_free_factor(&factor, &common);
    factor = cholmod_analyze(S, &common);
    if (factor == nullptr)
      {
        const int status = common.status;
        cholmod_free_sparse(&S, &common);
        throw std::runtime_error("CHOLMOD failed in the analysis of a matrix of " +
                                 std::to_string(n) + " rows: " + cholmod_status_text(status) + ".");
      }
    cholmod_factorize(S, factor, &common);
    cholmod_free_sparse(&S, &common);
    const int status = common.status;
    // A failure to allocate or address the factor is not the scene's fault: say which it is.
    if (status != CHOLMOD_OK && status != CHOLMOD_NOT_POSDEF && status != CHOLMOD_DSMALL)
      throw std::runtime_error("CHOLMOD failed in the factorization of a matrix of " +
                               std::to_string(n) + " rows: " + cholmod_status_text(status) + ".");
    require(status == CHOLMOD_OK && factor->minor == n,
            "CHOLMOD: the matrix is not positive definite (leading minor " +
              std::to_string(factor->minor) + " of " + std::to_string(n) +
              "): the body or subdomain is not held as the scene claims.");
    if (factor->is_super && solves == Solves::project)
      supernodal = std::make_unique<SupernodalSolve>(*factor);
  }

  void
  CholmodSolver::solve(Vector<double> &v) const
  {
    Assert(v.size() == n, ExcDimensionMismatch(v.size(), n));
    if (n == 0)
      return;
    if (supernodal)
      supernodal->solve(v.begin());
    else
      solve_by_library(v);
  }

  void
  CholmodSolver::solve_by_library(Vector<double> &v) const
  {
    Assert(v.size() == n, ExcDimensionMismatch(v.size(), n));
    if (n == 0)
      return;
    AssertThrow(!values_moved,
                ExcMessage("CholmodSolver: the numbers of the factor have moved out of CHOLMOD."));
    if (b_work == nullptr)
      b_work = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &common);
    std::memcpy(b_work->x, v.begin(), n * sizeof(double));
    cholmod_solve2(CHOLMOD_A, factor, b_work, nullptr, &x_work, nullptr, &y_work, &e_work, &common);
    std::memcpy(v.begin(), x_work->x, n * sizeof(double));
  }

  void
  CholmodSolver::solve_half(Vector<double> &v, const bool transpose) const
  {
    if (n == 0)
      return;
    AssertThrow(!values_moved,
                ExcMessage("CholmodSolver: the numbers of the factor have moved out of CHOLMOD."));
    if (b_work == nullptr)
      b_work = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &common);
    std::memcpy(b_work->x, v.begin(), n * sizeof(double));
    const int first  = transpose ? CHOLMOD_Lt : CHOLMOD_P;
    const int second = transpose ? CHOLMOD_Pt : CHOLMOD_L;
    cholmod_solve2(first, factor, b_work, nullptr, &x_work, nullptr, &y_work, &e_work, &common);
    cholmod_solve2(second, factor, x_work, nullptr, &b_work, nullptr, &y_work, &e_work, &common);
    std::memcpy(v.begin(), b_work->x, n * sizeof(double));
  }

  void
  CholmodSolver::move_factor_values(double *destination)
  {
    AssertThrow(supernodal != nullptr,
                ExcMessage("CholmodSolver: only a supernodal factor with the project's solves "
                           "can move."));
    const std::size_t n_values = supernodal->factor().n_values();
    std::memcpy(destination, factor->x, n_values * sizeof(double));
    cholmod_free(factor->xsize, sizeof(double), factor->x, &common);
    factor->x     = nullptr;
    factor->xsize = 0;
    values_moved  = true;
    supernodal->rebind_values(destination);
  }

  double
  CholmodSolver::reciprocal_condition_estimate() const
  {
    AssertThrow(!values_moved,
                ExcMessage("CholmodSolver: the numbers of the factor have moved out of CHOLMOD."));
    return n == 0 ? 1.0 : cholmod_rcond(factor, &common);
  }
} // namespace FetiContact
