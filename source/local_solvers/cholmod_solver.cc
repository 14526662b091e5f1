#include <feticontact/base/input_parsing.h>
#include <feticontact/base/mpi_tools.h>
#include <feticontact/local_solvers/cholmod_solver.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <fcntl.h>
#include <random>
#include <stdexcept>
#include <string>
#include <sys/mman.h>
#include <type_traits>
#include <unistd.h>
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
    release_shared();
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
    cholmod_sparse *S = upper_triangle<int>(A, common);
    supernodal.reset();
    release_shared();
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
    AssertThrow(library_factor() != nullptr,
                ExcMessage("CholmodSolver: no factor (sharing it failed)."));
    if (b_work == nullptr)
      b_work = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &common);
    std::memcpy(b_work->x, v.begin(), n * sizeof(double));
    cholmod_solve2(
      CHOLMOD_A, library_factor(), b_work, nullptr, &x_work, nullptr, &y_work, &e_work, &common);
    std::memcpy(v.begin(), x_work->x, n * sizeof(double));
  }

  void
  CholmodSolver::solve_half(Vector<double> &v, const bool transpose) const
  {
    if (n == 0)
      return;
    AssertThrow(library_factor() != nullptr,
                ExcMessage("CholmodSolver: no factor (sharing it failed)."));
    if (b_work == nullptr)
      b_work = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &common);
    std::memcpy(b_work->x, v.begin(), n * sizeof(double));
    const int first  = transpose ? CHOLMOD_Lt : CHOLMOD_P;
    const int second = transpose ? CHOLMOD_Pt : CHOLMOD_L;
    cholmod_solve2(
      first, library_factor(), b_work, nullptr, &x_work, nullptr, &y_work, &e_work, &common);
    cholmod_solve2(
      second, library_factor(), x_work, nullptr, &b_work, nullptr, &y_work, &e_work, &common);
    std::memcpy(v.begin(), b_work->x, n * sizeof(double));
  }

  double
  CholmodSolver::reciprocal_condition_estimate() const
  {
    return n == 0 ? 1.0 : cholmod_rcond(library_factor(), &common);
  }

  /**
   * Byte offsets of a supernodal factor's arrays in a shared segment: the numbers first (at
   * 0), then the index arrays, each on a cache line.
   */
  struct CholmodSolver::FactorLayout
  {
    explicit FactorLayout(const cholmod_factor &L)
    {
      std::size_t at    = 0;
      const auto  place = [&](const std::size_t bytes) {
        const std::size_t start = at;
        at += (bytes + 63) / 64 * 64;
        return start;
      };
      x        = place(sizeof(double) * L.xsize);
      perm     = place(sizeof(int) * L.n);
      colcount = place(sizeof(int) * L.n);
      super    = place(sizeof(int) * (L.nsuper + 1));
      pi       = place(sizeof(int) * (L.nsuper + 1));
      px       = place(sizeof(int) * (L.nsuper + 1));
      s        = place(sizeof(int) * L.ssize);
      bytes    = std::max<std::size_t>(at, 64);
    }
    /** The offsets of L.x, Perm, ColCount, super, pi, px, s. */
    std::size_t x, perm, colcount, super, pi, px, s;
    /** The size of the segment. */
    std::size_t bytes;
  };

  namespace
  {
    /**
     * Moves @p bytes from @p source to the segment @p fd, mapped at @p destination, from its
     * offset @p offset on, in pieces: each piece's pages of the segment are reserved
     * (posix_fallocate: a full /dev/shm fails here, not with SIGBUS at the first write), the
     * piece copied, and the whole pages of @p source copied so far given back to the system
     * (MADV_DONTNEED; @p source is freed right after). So neither the process nor the node ever
     * holds the numbers twice, beyond one piece. Returns the error, or an empty string.
     */
    std::string
    move_to_segment(const int         fd,
                    char *const       destination,
                    const std::size_t offset,
                    char *const       source,
                    const std::size_t bytes)
    {
      const std::uintptr_t page  = sysconf(_SC_PAGESIZE);
      const std::size_t    piece = std::size_t(16) << 20;
      const auto           start = reinterpret_cast<std::uintptr_t>(source);
      for (std::size_t done = 0; done < bytes; done += piece)
        {
          const std::size_t n = std::min(piece, bytes - done);
          if (const int reserved = posix_fallocate(fd, offset + done, n); reserved != 0)
            return std::strerror(reserved);
          std::memcpy(destination + offset + done, source + done, n);
          // The whole pages of [source, source + done + n) not given back yet.
          const std::uintptr_t begin =
            done == 0 ? (start + page - 1) / page * page : (start + done) / page * page;
          const std::uintptr_t end = (start + done + n) / page * page;
          if (end > begin)
            madvise(reinterpret_cast<void *>(begin), end - begin, MADV_DONTNEED);
        }
      return {};
    }

    /** A name for a new segment on the node: the process, a random number and a count. */
    std::string
    new_segment_name()
    {
      static std::atomic<unsigned long> n_segments{0};
      static const unsigned long long   tag = std::random_device()();
      return "/feticontact." + std::to_string(getpid()) + "." + std::to_string(tag) + ".factor." +
             std::to_string(n_segments++);
    }
  } // namespace

  void
  CholmodSolver::share_factor(const MPI_Comm node)
  {
    int rank = 0, n_ranks = 1;
    MPI_Comm_rank(node, &rank);
    MPI_Comm_size(node, &n_ranks);
    if (n_ranks == 1)
      return;
    AssertThrow(solves == Solves::library,
                ExcMessage("CholmodSolver: only a factor with CHOLMOD's solves is shared."));
    // Rank 0's factor (supernodal: CHOLMOD_SUPERNODAL) without its pointers, and the name.
    const bool has_factor = rank != 0 || (factor != nullptr && factor->is_super);
    AssertThrow(Utilities::MPI::min(has_factor ? 1 : 0, node) == 1,
                ExcMessage("CholmodSolver: share_factor() needs rank 0's supernodal factor."));
    cholmod_factor header{};
    if (rank == 0)
      header = *factor;
    MPI_Bcast(&header, sizeof(header), MPI_BYTE, 0, node);
    n = header.n;
    const FactorLayout layout(header);
    const std::string  name = Utilities::MPI::broadcast(node, new_segment_name(), 0);
    // The name exists only until the other ranks have opened the segment: rank 0 creates it,
    // the others open it, rank 0 removes the name. Then rank 0 moves its factor in, and the
    // others map it.
    int         fd = -1;
    std::string error;
    if (rank == 0)
      {
        fd = shm_open(name.c_str(), O_CREAT | O_EXCL | O_RDWR, 0600);
        if (fd < 0 || ftruncate(fd, layout.bytes) != 0)
          error = std::strerror(errno);
      }
    error = MPITools::first_error(node, error);
    if (error.empty() && rank != 0 && (fd = shm_open(name.c_str(), O_RDONLY, 0)) < 0)
      error = std::strerror(errno);
    error = MPITools::first_error(node, error);
    if (rank == 0 && fd >= 0)
      shm_unlink(name.c_str());
    if (error.empty() && rank == 0)
      error = move_factor_to_segment(fd, layout);
    error = MPITools::first_error(node, error);
    if (error.empty() && rank != 0)
      error = map_segment(fd, layout.bytes);
    if (fd >= 0)
      close(fd);
    error = MPITools::first_error(node, error);
    if (!error.empty())
      {
        // No rank keeps a factor: the solves refuse from now on.
        release_shared();
        if (factor != nullptr)
          cholmod_free_factor(&factor, &common);
        throw std::runtime_error("Shared memory of " +
                                 std::to_string(layout.bytes / (1024 * 1024) + 1) +
                                 " MiB for a factor of " + std::to_string(header.n) +
                                 " rows shared by the ranks of a node (" + name + "): " + error +
                                 ". Enlarge /dev/shm, or set FETI/Coarse factor = per rank.");
      }
    view_segment(header, layout);
  }

  std::string
  CholmodSolver::move_factor_to_segment(const int fd, const FactorLayout &layout)
  {
    void *address = mmap(nullptr, layout.bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (address == MAP_FAILED)
      return std::strerror(errno);
    segment          = address;
    segment_bytes    = layout.bytes;
    char *const base = static_cast<char *>(segment);
    // The index arrays (after the numbers), then the numbers piece by piece.
    if (const int reserved = posix_fallocate(fd, layout.perm, layout.bytes - layout.perm);
        reserved != 0)
      return std::strerror(reserved);
    std::memcpy(base + layout.perm, factor->Perm, sizeof(int) * factor->n);
    std::memcpy(base + layout.colcount, factor->ColCount, sizeof(int) * factor->n);
    std::memcpy(base + layout.super, factor->super, sizeof(int) * (factor->nsuper + 1));
    std::memcpy(base + layout.pi, factor->pi, sizeof(int) * (factor->nsuper + 1));
    std::memcpy(base + layout.px, factor->px, sizeof(int) * (factor->nsuper + 1));
    std::memcpy(base + layout.s, factor->s, sizeof(int) * factor->ssize);
    const std::string error = move_to_segment(
      fd, base, layout.x, static_cast<char *>(factor->x), sizeof(double) * factor->xsize);
    cholmod_free_factor(&factor, &common);
    return error;
  }

  std::string
  CholmodSolver::map_segment(const int fd, const std::size_t bytes)
  {
    // MAP_POPULATE: the pages are mapped now, in the setup, not at the first solve.
    void *address = mmap(nullptr, bytes, PROT_READ, MAP_SHARED | MAP_POPULATE, fd, 0);
    if (address == MAP_FAILED)
      return std::strerror(errno);
    segment       = address;
    segment_bytes = bytes;
    return {};
  }

  void
  CholmodSolver::view_segment(const cholmod_factor &header, const FactorLayout &layout)
  {
    char *const base = static_cast<char *>(segment);
    shared           = std::make_unique<cholmod_factor>(header);
    shared->Perm     = base + layout.perm;
    shared->ColCount = base + layout.colcount;
    shared->IPerm    = nullptr;
    shared->super    = base + layout.super;
    shared->pi       = base + layout.pi;
    shared->px       = base + layout.px;
    shared->s        = base + layout.s;
    shared->x        = base + layout.x;
    shared->p = shared->i = shared->z = shared->nz = shared->next = shared->prev = nullptr;
  }

  void
  CholmodSolver::release_shared()
  {
    if (segment != nullptr)
      munmap(segment, segment_bytes);
    segment       = nullptr;
    segment_bytes = 0;
    shared.reset();
  }
} // namespace FetiContact
