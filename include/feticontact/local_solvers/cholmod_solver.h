#pragma once

#include <feticontact/local_solvers/local_solver.h>
#include <feticontact/local_solvers/supernodal_solve.h>

#include <cholmod.h>

#include <memory>
#include <mpi.h>
#include <string>

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

  /** What CHOLMOD's status code @p status (cholmod_common::status) means, for error messages. */
  std::string
  cholmod_status_text(const int status);

  /** What solve_by_long_cholmod() measured. */
  struct LongCholmodStatistics
  {
    /** Entries of the factor L (cholmod_common::lnz). */
    double factor_entries = 0;
    /** Wall seconds of the analysis and factorization, and of the two triangular solves. */
    double factorization_seconds = 0, solve_seconds = 0;
  };

  /**
   * u ← K⁻¹u (@p u holds the right-hand side on entry) for a symmetric positive definite @p K, by
   * CHOLMOD's supernodal Cholesky through its 64-bit interface (cholmod_l_*). For the undecomposed
   * body: its factor may hold more entries than the 32-bit CholmodSolver can address (the brick at
   * 10⁶ unknowns: 1.9·10⁹ entries, near the 32-bit limit of 2.1·10⁹; there the 32-bit analysis
   * returned no factor). Used by the comparison with a
   * monolithic solve (Verification) and by benchmarks/monolithic_solve. Throws InputError if K is
   * not positive definite, std::runtime_error naming CHOLMOD's status if it fails otherwise (out of
   * memory, too large); CHOLMOD's memory is freed in both cases.
   */
  LongCholmodStatistics
  solve_by_long_cholmod(const dealii::SparseMatrix<double> &K, dealii::Vector<double> &u);

  /**
   * SuiteSparse CHOLMOD, supernodal Cholesky LLᵀ with CHOLMOD's choice of fill-reducing ordering
   * (AMD or METIS). The fastest backend measured here (doc/local_solvers.md) and the default.
   * CHOLMOD factorizes. The subdomains' solves with its factor are the project's
   * (SupernodalSolve), about 1.4 times as fast as CHOLMOD's own on FETI's subdomains
   * (doc/local_solvers.md); solve_by_library() keeps CHOLMOD's as the reference.
   */
  class CholmodSolver : public LocalSolver
  {
  public:
    /** Whose triangular solves solve() makes with CHOLMOD's factor. */
    enum class Solves
    {
      /** CHOLMOD's own (cholmod_solve2): the coarse problem GGᵀ, the verification. */
      library,
      /** The project's SupernodalSolve: the subdomains' backend 'cholmod'. */
      project
    };

    /**
     * The backend 'cholmod' is CholmodSolver(Solves::project); 'cholmod-library-solves' is
     * CholmodSolver(Solves::library), which reproduces the numbers of runs made before the
     * project's solves to the last digit.
     */
    explicit CholmodSolver(const Solves solves = Solves::library);
    ~CholmodSolver() override;

    void
    factorize(const dealii::SparseMatrix<double> &A) override;
    void
    solve(dealii::Vector<double> &x) const override;
    /** x ← A⁻¹ x by CHOLMOD's own solve (cholmod_solve2): the reference for solve(). */
    void
    solve_by_library(dealii::Vector<double> &x) const;
    /** CHOLMOD's factor (for its statistics: entries, supernodes). */
    const cholmod_factor &
    factor_of_library() const
    {
      return *library_factor();
    }
    /** Each object has its own cholmod_common and work arrays. */
    bool
    thread_safe() const override
    {
      return true;
    }
    std::string
    name() const override
    {
      return solves == Solves::project ? "cholmod" : "cholmod-library-solves";
    }

    /**
     * The factor that solve() uses, if the solves are the project's (Solves::project and a
     * supernodal factor); nullptr otherwise.
     */
    const SupernodalFactor *
    supernodal_factor() const
    {
      return supernodal ? &supernodal->factor() : nullptr;
    }

    /**
     * Makes the factor of rank 0 of @p node, which alone has factorized, the factor of every rank
     * of @p node: rank 0 copies its arrays into a segment of memory shared by the ranks of the
     * node (POSIX shared memory, /dev/shm) and frees CHOLMOD's; every rank maps the segment
     * read-only and solves with it from then on by CHOLMOD's own solves. The node then holds one
     * factor instead of one per rank, and every rank's solves give the numbers of a factor of its
     * own. Only with library solves; the other ranks' factorize() must not have been called.
     * Collective on @p node; nothing to do on a node of one rank. Throws std::runtime_error on
     * every rank of the node if the segment cannot be made (/dev/shm full or too small).
     */
    void
    share_factor(const MPI_Comm node);

    /** The bytes of the shared segment this rank has mapped (share_factor()), or 0. */
    std::size_t
    shared_bytes() const
    {
      return segment_bytes;
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
    /** CHOLMOD's factor of this rank, or the view of the shared one (share_factor()). */
    cholmod_factor *
    library_factor() const
    {
      return shared ? shared.get() : factor;
    }

    /** Where a factor's arrays lie in a shared segment (cholmod_solver.cc). */
    struct FactorLayout;

    /** Unmaps the shared segment, if any. */
    void
    release_shared();
    /**
     * share_factor() on rank 0: maps the segment @p fd, moves this factor's arrays into it at
     * the offsets of @p layout and frees CHOLMOD's factor. Returns the error, or "".
     */
    std::string
    move_factor_to_segment(const int fd, const FactorLayout &layout);
    /** share_factor() on the other ranks: maps @p bytes of the segment @p fd read-only. */
    std::string
    map_segment(const int fd, const std::size_t bytes);
    /** Points the view of the shared factor (@p header's sizes) into the mapped segment. */
    void
    view_segment(const cholmod_factor &header, const FactorLayout &layout);

    const Solves                     solves;
    mutable cholmod_common           common;
    cholmod_factor                  *factor = nullptr;
    std::unique_ptr<SupernodalSolve> supernodal;
    mutable cholmod_dense           *x_work = nullptr, *y_work = nullptr, *e_work = nullptr;
    mutable cholmod_dense           *b_work = nullptr;
    std::size_t                      n      = 0;
    /**
     * After share_factor(): a factor whose arrays point into the shared segment at @p segment
     * (@p segment_bytes mapped). CHOLMOD only reads it; it is never passed to cholmod_free_*.
     */
    std::unique_ptr<cholmod_factor> shared;
    void                           *segment       = nullptr;
    std::size_t                     segment_bytes = 0;
  };
} // namespace FetiContact
