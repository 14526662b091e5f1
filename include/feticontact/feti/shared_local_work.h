#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/local_solvers/supernodal_solve.h>
#include <feticontact/subdomain/subdomain.h>

#include <mpi.h>
#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * B_i of one subdomain in coordinate form: rows (dual indices), DoFs of subdomain i, values,
   * and the slot of each entry (its index among the nonzeros of B, where B_i u_i is written).
   */
  struct BlockOfB
  {
    std::vector<unsigned int> row, dof, slot;
    std::vector<double>       value;
  };

  /**
   * The local work of the multiplications by F = B K⁺ Bᵀ (per subdomain: Bᵀ_i x, the solve with
   * the factor of K̃_i, B_i u_i) shared by the MPI ranks of one node, with the balance made anew
   * in every multiplication.
   *
   * With subdomains assigned to ranks once, every multiplication waits for the slowest rank. On a
   * virtual machine the cores' speed changes within a run (doc/performance.md, "MPI on this
   * machine": local work 20.4 against 15.0 s on two ranks with equal subdomains), so no fixed
   * assignment is balanced. Here every rank keeps a reserve, a fraction of its subdomains whose
   * factors live in memory shared by the node's ranks: right after such a subdomain is
   * factorized, take_factor() moves the numbers of its factor out of CHOLMOD into a shared
   * segment of its own (the factors stay stored once, and the memory CHOLMOD frees is reused by
   * the next factorization). share() copies their supernodal structure, permutation, DoFs fixed
   * to zero and blocks B_i into a shared window and maps every rank's segments. In every
   * multiplication each rank solves its other subdomains as before (DualProblem), then takes
   * subdomains from its own reserve and, once that is empty, from the other ranks' reserves: one
   * counter per reserve in shared memory (an atomic increment), and B_i u_i goes into shared
   * slots. A rank that is slower takes fewer subdomains.
   *
   * Only a reserve, because sharing every factor cost 8–10 % more local work per rank on
   * balanced cores (doc/performance.md), most likely through the 4 KiB pages of shared memory
   * (Debian's default gives shared memory no transparent huge pages; the heap's factors sit in
   * 2 MiB pages). Measured on this project's virtual machine, a reserve of a quarter balanced the
   * ranks and paid off at 10⁵ unknowns but cost 10–15 % at 10⁶, so it is off by default
   * (FETI/Shared local work = 0).
   *
   * The work for a subdomain is the same operations in the same order whichever rank does it
   * (the kernels of SupernodalSolve do not depend on the instruction set), and DualProblem sums
   * the slots in a fixed order, so F x is the same to the last bit as with the fixed assignment
   * and on one rank.
   *
   * Needs every rank on one node and the backend 'cholmod' (the project's supernodal solves);
   * possible() says whether that holds. Knows nothing of contact: it sees factors, DoFs and
   * entries of B.
   */
  class SharedLocalWork
  {
  public:
    /**
     * Whether the ranks of @p comm can share their local work with the backend
     * @p local_solver: more than one rank, all on one node, the backend 'cholmod'. Collective.
     */
    static bool
    possible(const MPI_Comm comm, const std::string &local_solver);

    /** Collective. */
    explicit SharedLocalWork(const MPI_Comm comm);

    ~SharedLocalWork();

    SharedLocalWork(const SharedLocalWork &) = delete;
    SharedLocalWork &
    operator=(const SharedLocalWork &) = delete;

    /**
     * Moves the numbers of the factor of @p subdomain (just factorized, backend 'cholmod') into
     * a shared segment. Not collective.
     */
    void
    take_factor(Subdomain &subdomain);

    /**
     * Makes the reserves of all ranks available to every rank: of the @p owned subdomains (with
     * their blocks @p B, in the same order) those passed to take_factor(), and @p n_slots
     * shared slots. Collective, once.
     */
    void
    share(const std::vector<Subdomain *> &owned,
          const std::vector<BlockOfB>    &B,
          const unsigned int              n_slots);

    /** Whether the factor of subdomain @p subdomain (global index) is in this rank's reserve. */
    bool
    holds(const unsigned int subdomain) const;

    /** The shared slots: one number per nonzero of B, read and written by every rank. */
    double *
    slots() const
    {
      return shared_slots;
    }

    /**
     * Writes B_i K_i⁺ B_iᵀ x into the slots of the subdomains of all reserves, taken by whichever
     * rank is free, and returns how many this rank solved. Collective; returns once this rank
     * found no subdomain left (call synchronize() before reading the slots).
     */
    unsigned int
    apply(const dealii::Vector<double> &x) const;

    /**
     * Makes every rank's writes to the shared memory visible to all and waits for all ranks
     * (MPI_Win_sync and a barrier). Collective.
     */
    void
    synchronize() const;

    /**
     * Resets the counters of apply() for the next multiplication: between two calls of
     * synchronize() that follow apply() (every rank may call it).
     */
    void
    reset_counter() const;

    /** The bytes of shared memory this rank allocated (factors, structure, blocks, slots). */
    std::size_t
    shared_bytes() const
    {
      return own_bytes;
    }

  private:
    /** One subdomain in the shared memory: its factor and its block of B. */
    struct Task
    {
      SupernodalFactor L;
      unsigned int     n_fixed = 0, n_entries = 0;
      const int       *fixed = nullptr, *row = nullptr, *dof = nullptr, *slot = nullptr;
      const double    *value = nullptr;
    };

    /** A mapped shared segment with the numbers of one factor. */
    struct Segment
    {
      unsigned int subdomain = 0;
      void        *address   = nullptr;
      std::size_t  bytes     = 0;
    };

    /**
     * The numbers of the factor of subdomain @p s (@p n_values of them): this rank's own
     * segment, or the other rank's segment mapped read-only (kept in mapped_segments).
     */
    const double *
    factor_values(const unsigned int s, const std::size_t n_values);

    /** The name of the segment of subdomain @p s ("/feticontact.<job>.<s>"). */
    std::string
    segment_name(const unsigned int s) const;

    MPI_Comm             comm;
    int                  this_rank = 0;
    long long            job       = 0;
    std::vector<Segment> own_segments, mapped_segments;
    MPI_Win              window = MPI_WIN_NULL, slot_window = MPI_WIN_NULL;
    /** The subdomains of all reserves, rank by rank (those of rank r from first_task_of_rank[r]).
     */
    std::vector<Task>         tasks;
    std::vector<unsigned int> first_task_of_rank;
    /** The counters of the reserves, in rank 0's part of the window. */
    std::vector<int *> counters;
    double            *shared_slots = nullptr;
    std::size_t        own_bytes    = 0;
    /** Whether share() has removed the names of this rank's segments. */
    bool names_removed = false;
    /** Work arrays of one solve (sized for the largest subdomain). */
    mutable std::vector<double> u, permuted, rows_of_supernode;
  };
} // namespace FetiContact
