#include <feticontact/base/mpi_tools.h>
#include <feticontact/feti/shared_local_work.h>
#include <feticontact/local_solvers/cholmod_solver.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

namespace FetiContact
{
  using namespace dealii;

  // A failure here is not the user's input (shared memory exhausted, /dev/shm not writable)
  // and may hit one rank only: AssertThrow, which ends all ranks (main.cc), not InputError.
  namespace
  {
    /** The sizes of one subdomain's arrays in the shared memory, as all ranks learn them. */
    struct TaskSizes
    {
      long long subdomain, rank, offset;
      long long n, n_supernodes, n_row_indices, n_values, n_fixed, n_entries;
    };

    /** Byte offsets of the arrays of one subdomain, from the start of its record. */
    struct Layout
    {
      explicit Layout(const TaskSizes &t)
      {
        std::size_t at      = 0;
        const auto  doubles = [&](const long long count) {
          const std::size_t start = at;
          at += sizeof(double) * count;
          return start;
        };
        const auto ints = [&](const long long count) {
          const std::size_t start = at;
          at += sizeof(int) * count;
          return start;
        };
        value = doubles(t.n_entries);
        super = ints(t.n_supernodes + 1);
        pi    = ints(t.n_supernodes + 1);
        px    = ints(t.n_supernodes + 1);
        s     = ints(t.n_row_indices);
        perm  = ints(t.n);
        fixed = ints(t.n_fixed);
        row   = ints(t.n_entries);
        dof   = ints(t.n_entries);
        slot  = ints(t.n_entries);
        bytes = (at + 63) / 64 * 64; // the next record starts on a cache line
      }
      std::size_t value, super, pi, px, s, perm, fixed, row, dof, slot, bytes;
    };

    CholmodSolver *
    cholmod_of(Subdomain &s)
    {
      auto *solver = dynamic_cast<CholmodSolver *>(s.local_solver());
      return solver != nullptr && solver->supernodal_factor() != nullptr ? solver : nullptr;
    }

    template <typename T>
    void
    copy_to(char *base, const std::size_t offset, const T *from, const std::size_t count)
    {
      if (count > 0)
        std::memcpy(base + offset, from, count * sizeof(T));
    }

    /**
     * The sizes of the records of the subdomains @p owned[i], i in @p in_reserve, of rank
     * @p rank, one after the other from offset 0.
     */
    std::vector<TaskSizes>
    record_sizes(const std::vector<Subdomain *>  &owned,
                 const std::vector<BlockOfB>     &B,
                 const std::vector<unsigned int> &in_reserve,
                 const int                        rank)
    {
      std::vector<TaskSizes> sizes(in_reserve.size());
      std::size_t            bytes = 0;
      for (unsigned int j = 0; j < in_reserve.size(); ++j)
        {
          const unsigned int      i = in_reserve[j];
          const SupernodalFactor &L = *cholmod_of(*owned[i])->supernodal_factor();
          sizes[j]                  = {owned[i]->global_index,
                                       rank,
                                       static_cast<long long>(bytes),
                                       static_cast<long long>(L.n),
                                       static_cast<long long>(L.n_supernodes),
                      L.n_supernodes == 0 ? 0 : L.pi[L.n_supernodes],
                                       static_cast<long long>(L.n_values()),
                                       static_cast<long long>(owned[i]->kernel_fixing_dofs.size()),
                                       static_cast<long long>(B[i].row.size())};
          bytes += Layout(sizes[j]).bytes;
        }
      return sizes;
    }

    /**
     * Writes the record of @p subdomain (sizes @p sizes) with its block @p b of B at @p record:
     * the factor's structure, the DoFs fixed to zero and B_i (the numbers of the factor have
     * their own segment).
     */
    void
    write_record(char *const      record,
                 const TaskSizes &sizes,
                 Subdomain       &subdomain,
                 const BlockOfB  &b)
    {
      const Layout            layout(sizes);
      const SupernodalFactor &L     = *cholmod_of(subdomain)->supernodal_factor();
      const auto              ns    = L.n_supernodes + 1;
      const auto             &fixed = subdomain.kernel_fixing_dofs;
      copy_to(record, layout.value, b.value.data(), b.value.size());
      copy_to(record, layout.super, L.super, ns);
      copy_to(record, layout.pi, L.pi, ns);
      copy_to(record, layout.px, L.px, ns);
      copy_to(record, layout.s, L.s, sizes.n_row_indices);
      copy_to(record, layout.perm, L.perm, L.n);
      std::vector<int> as_int(fixed.begin(), fixed.end());
      copy_to(record, layout.fixed, as_int.data(), as_int.size());
      as_int.assign(b.row.begin(), b.row.end());
      copy_to(record, layout.row, as_int.data(), as_int.size());
      as_int.assign(b.dof.begin(), b.dof.end());
      copy_to(record, layout.dof, as_int.data(), as_int.size());
      as_int.assign(b.slot.begin(), b.slot.end());
      copy_to(record, layout.slot, as_int.data(), as_int.size());
    }
  } // namespace

  bool
  SharedLocalWork::possible(const MPI_Comm comm, const std::string &local_solver)
  {
    int n_ranks = 1;
    MPI_Comm_size(comm, &n_ranks);
    if (n_ranks == 1 || local_solver != "cholmod")
      return false;
    MPI_Comm node;
    MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
    int n_node_ranks = 1;
    MPI_Comm_size(node, &n_node_ranks);
    MPI_Comm_free(&node);
    int ok = n_node_ranks == n_ranks;
    MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, comm);
    return ok != 0;
  }

  SharedLocalWork::SharedLocalWork(const MPI_Comm comm)
    : comm(comm)
  {
    MPI_Comm_rank(comm, &this_rank);
    // The segments' names carry the process id of rank 0: unique on the node while it runs.
    job = getpid();
    MPI_Bcast(&job, 1, MPI_LONG_LONG, 0, comm);
  }

  const double *
  SharedLocalWork::factor_values(const unsigned int subdomain, const std::size_t n_values)
  {
    for (const Segment &segment : own_segments)
      if (segment.subdomain == subdomain)
        return static_cast<const double *>(segment.address);
    const std::string name    = segment_name(subdomain);
    const int         fd      = shm_open(name.c_str(), O_RDONLY, 0);
    const std::size_t n_bytes = std::max<std::size_t>(n_values * sizeof(double), 1);
    void     *address = fd < 0 ? MAP_FAILED : mmap(nullptr, n_bytes, PROT_READ, MAP_SHARED, fd, 0);
    const int error   = errno;
    if (fd >= 0)
      close(fd);
    AssertThrow(address != MAP_FAILED,
                ExcMessage("Shared memory of the factor of subdomain " + std::to_string(subdomain) +
                           " (" + name + "): " + std::strerror(error) +
                           ". Set FETI/Shared local work = 0 to run without it."));
    mapped_segments.push_back({subdomain, address, n_bytes});
    return static_cast<const double *>(address);
  }

  std::string
  SharedLocalWork::segment_name(const unsigned int s) const
  {
    return "/feticontact." + std::to_string(job) + "." + std::to_string(s);
  }

  void
  SharedLocalWork::take_factor(Subdomain &subdomain)
  {
    CholmodSolver *solver = cholmod_of(subdomain);
    AssertThrow(solver != nullptr,
                ExcMessage("SharedLocalWork: subdomain " + std::to_string(subdomain.global_index) +
                           " is not factorized by CHOLMOD with the project's solves."));
    // In increasing order, so that holds() can search the reserve by bisection.
    AssertThrow(own_segments.empty() || own_segments.back().subdomain < subdomain.global_index,
                ExcMessage("SharedLocalWork: take_factor() needs the subdomains of the reserve "
                           "in increasing order."));
    const std::size_t page  = sysconf(_SC_PAGESIZE);
    const std::size_t bytes = std::max<std::size_t>(
      (solver->supernodal_factor()->n_values() * sizeof(double) + page - 1) / page * page, page);
    const std::string name = segment_name(subdomain.global_index);
    const int         fd   = shm_open(name.c_str(), O_CREAT | O_EXCL | O_RDWR, 0600);
    AssertThrow(fd >= 0,
                ExcMessage("Shared memory for the factor of subdomain " +
                           std::to_string(subdomain.global_index) + " (" + name +
                           "): " + std::strerror(errno) +
                           ". Set FETI/Shared local work = 0 to run without it."));
    // posix_fallocate reserves the pages: a full /dev/shm fails here, not with SIGBUS at the
    // first write.
    void *address = MAP_FAILED;
    int   error   = ftruncate(fd, bytes) == 0 ? posix_fallocate(fd, 0, bytes) : errno;
    if (error == 0)
      {
        address = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
        error   = errno;
      }
    close(fd);
    if (address == MAP_FAILED)
      shm_unlink(name.c_str());
    AssertThrow(address != MAP_FAILED,
                ExcMessage("Shared memory of " + std::to_string(bytes) +
                           " bytes for the factor of subdomain " +
                           std::to_string(subdomain.global_index) + ": " + std::strerror(error) +
                           ". Set FETI/Shared local work = 0 to run without it."));
    own_segments.push_back({subdomain.global_index, address, bytes});
    own_bytes += bytes;
#ifdef MADV_POPULATE_WRITE
    // The pages in one call rather than one fault each (on a virtual machine a fault on memory
    // touched for the first time is costly); without it the copy below faults them in.
    madvise(address, bytes, MADV_POPULATE_WRITE);
#endif
    solver->move_factor_values(static_cast<double *>(address));
  }

  void
  SharedLocalWork::share(const std::vector<Subdomain *> &owned,
                         const std::vector<BlockOfB>    &B,
                         const unsigned int              n_slots)
  {
    AssertThrow(B.size() == owned.size(), ExcDimensionMismatch(B.size(), owned.size()));
    AssertThrow(tasks.empty(), ExcMessage("SharedLocalWork::share() is called once."));
    int n_ranks = 1;
    MPI_Comm_size(comm, &n_ranks);

    // The records of this rank's subdomains in shared memory, one after the other.
    std::vector<unsigned int> in_reserve;
    for (unsigned int i = 0; i < owned.size(); ++i)
      if (holds(owned[i]->global_index))
        in_reserve.push_back(i);
    AssertThrow(in_reserve.size() == own_segments.size(),
                ExcMessage("SharedLocalWork: a factor in shared memory belongs to no owned "
                           "subdomain."));
    const std::vector<TaskSizes> own = record_sizes(owned, B, in_reserve, this_rank);
    const std::size_t bytes = own.empty() ? 0 : own.back().offset + Layout(own.back()).bytes;
    // Rank 0's window: one counter per rank, each on a cache line of its own, then the slots.
    const std::size_t slot_bytes = this_rank == 0 ? 64 * n_ranks + sizeof(double) * n_slots : 0;
    own_bytes += bytes + slot_bytes;

    MPI_Info info;
    MPI_Info_create(&info);
    MPI_Info_set(info, "alloc_shared_noncontig", "true");
    char *base = nullptr;
    MPI_Win_allocate_shared(bytes, 1, info, comm, &base, &window);
    char *slot_base = nullptr;
    MPI_Win_allocate_shared(slot_bytes, 1, info, comm, &slot_base, &slot_window);
    MPI_Info_free(&info);
    MPI_Win_lock_all(MPI_MODE_NOCHECK, window);
    MPI_Win_lock_all(MPI_MODE_NOCHECK, slot_window);

    for (unsigned int j = 0; j < in_reserve.size(); ++j)
      write_record(base + own[j].offset, own[j], *owned[in_reserve[j]], B[in_reserve[j]]);

    // Every rank's records, rank by rank in the order of the subdomains, and the other ranks'
    // factors.
    auto all = MPITools::all_gather(comm, own);
    std::sort(all.begin(), all.end(), [](const TaskSizes &a, const TaskSizes &b) {
      return a.rank < b.rank || (a.rank == b.rank && a.subdomain < b.subdomain);
    });
    first_task_of_rank.assign(n_ranks + 1, 0);
    for (const TaskSizes &t : all)
      ++first_task_of_rank[t.rank + 1];
    for (int r = 0; r < n_ranks; ++r)
      first_task_of_rank[r + 1] += first_task_of_rank[r];
    std::vector<char *> rank_base(n_ranks, nullptr);
    for (int r = 0; r < n_ranks; ++r)
      {
        MPI_Aint size       = 0;
        int      disp_unit  = 1;
        char    *query_base = nullptr;
        MPI_Win_shared_query(window, r, &size, &disp_unit, &query_base);
        rank_base[r] = query_base;
      }
    {
      MPI_Aint size      = 0;
      int      disp_unit = 1;
      MPI_Win_shared_query(slot_window, 0, &size, &disp_unit, &slot_base);
      counters.resize(n_ranks);
      for (int r = 0; r < n_ranks; ++r)
        counters[r] = reinterpret_cast<int *>(slot_base + 64 * r);
      shared_slots = reinterpret_cast<double *>(slot_base + 64 * n_ranks);
    }
    tasks.resize(all.size());
    for (unsigned int t = 0; t < all.size(); ++t)
      {
        const Layout layout(all[t]);
        const char  *record = rank_base[all[t].rank] + all[t].offset;
        const auto   ints   = [&](const std::size_t offset) {
          return reinterpret_cast<const int *>(record + offset);
        };
        const double *values = factor_values(all[t].subdomain, all[t].n_values);
        Task         &task   = tasks[t];
        task.L.n             = all[t].n;
        task.L.n_supernodes  = all[t].n_supernodes;
        task.L.super         = ints(layout.super);
        task.L.pi            = ints(layout.pi);
        task.L.px            = ints(layout.px);
        task.L.s             = ints(layout.s);
        task.L.perm          = ints(layout.perm);
        task.L.x             = values;
        task.n_fixed         = all[t].n_fixed;
        task.n_entries       = all[t].n_entries;
        task.fixed           = ints(layout.fixed);
        task.row             = ints(layout.row);
        task.dof             = ints(layout.dof);
        task.slot            = ints(layout.slot);
        task.value           = reinterpret_cast<const double *>(record + layout.value);
      }
    if (this_rank == 0)
      reset_counter();
    synchronize();
    // Every rank has mapped the segments it needs: the names can go (the memory stays until
    // the last rank unmaps it, also if a rank ends abnormally).
    for (const Segment &segment : own_segments)
      shm_unlink(segment_name(segment.subdomain).c_str());
    names_removed = true;

    std::size_t max_n = 0, max_rows = 0;
    for (const Task &task : tasks)
      {
        max_n    = std::max(max_n, task.L.n);
        max_rows = std::max(max_rows, task.L.max_supernode_rows());
      }
    u.resize(max_n);
    permuted.resize(max_n);
    rows_of_supernode.resize(max_rows);
  }

  SharedLocalWork::~SharedLocalWork()
  {
    for (const Segment &segment : own_segments)
      {
        if (!names_removed)
          shm_unlink(segment_name(segment.subdomain).c_str());
        munmap(segment.address, segment.bytes);
      }
    for (const Segment &segment : mapped_segments)
      munmap(segment.address, segment.bytes);
    for (MPI_Win *w : {&window, &slot_window})
      if (*w != MPI_WIN_NULL)
        {
          MPI_Win_unlock_all(*w);
          MPI_Win_free(w);
        }
  }

  unsigned int
  SharedLocalWork::apply(const Vector<double> &x) const
  {
    // This rank's reserve first, then the other ranks' reserves: each list is handed out by
    // its own counter, to its owner and to ranks that are done with their own work alike.
    unsigned int n_solves = 0;
    const int    n_ranks  = counters.size();
    for (int q = 0; q < n_ranks; ++q)
      {
        const int r = (this_rank + q) % n_ranks;
        const int n = first_task_of_rank[r + 1] - first_task_of_rank[r];
        for (;;)
          {
            const int t = __atomic_fetch_add(counters[r], 1, __ATOMIC_RELAXED);
            if (t >= n)
              break;
            const Task &task = tasks[first_task_of_rank[r] + t];
            double     *y    = u.data();
            // u = K_i⁺ B_iᵀ x, with the same operations in the same order as
            // DualProblem::set_Bt and Subdomain::apply_generalized_inverse.
            std::fill(y, y + task.L.n, 0.);
            for (unsigned int k = 0; k < task.n_entries; ++k)
              y[task.dof[k]] += task.value[k] * x[task.row[k]];
            for (unsigned int k = 0; k < task.n_fixed; ++k)
              y[task.fixed[k]] = 0;
            supernodal_solve(task.L, y, permuted.data(), rows_of_supernode.data());
            for (unsigned int k = 0; k < task.n_fixed; ++k)
              y[task.fixed[k]] = 0;
            for (unsigned int k = 0; k < task.n_entries; ++k)
              shared_slots[task.slot[k]] = task.value[k] * y[task.dof[k]];
            ++n_solves;
          }
      }
    return n_solves;
  }

  bool
  SharedLocalWork::holds(const unsigned int subdomain) const
  {
    // own_segments is ordered by subdomain (take_factor()): a bisection, so that share() and
    // DualProblem, which ask for every owned subdomain, take n log n steps, not n · reserve.
    const auto it = std::lower_bound(own_segments.begin(),
                                     own_segments.end(),
                                     subdomain,
                                     [](const Segment &segment, const unsigned int s) {
                                       return segment.subdomain < s;
                                     });
    return it != own_segments.end() && it->subdomain == subdomain;
  }

  void
  SharedLocalWork::synchronize() const
  {
    MPI_Win_sync(window);
    MPI_Win_sync(slot_window);
    MPI_Barrier(comm);
    MPI_Win_sync(window);
    MPI_Win_sync(slot_window);
  }

  void
  SharedLocalWork::reset_counter() const
  {
    for (int *counter : counters)
      __atomic_store_n(counter, 0, __ATOMIC_RELAXED);
  }
} // namespace FetiContact
