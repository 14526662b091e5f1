// coarse_problem [--sizes N1,N2,...] [--repeats R] [--methods replicated,per-node,distributed]:
// the cost of FETI's coarse problem GGᵀ for a cube of N × N × N cubic subdomains, G = RᵀBᵀ with
// the six rigid modes of every subdomain and the rows of B of a coarse TFETI mesh: four gluing
// points (three components each) on every face between two subdomains, one on every edge and
// corner shared with a diagonal neighbour, and four Dirichlet points on every face on x = 0.
// Three ways to factorize and solve it, side by side in one run (median of R):
//   replicated   CoarseProblem: every rank holds G in the columns that touch its subdomains,
//                assembles the rows of GGᵀ of its modes, and the rows are gathered; every rank
//                factorizes GGᵀ by CHOLMOD and solves alone (FETI/Coarse factor = per rank);
//   per-node     the same, but the first rank of the node alone factorizes GGᵀ and the node's
//                ranks solve with the one factor in shared memory (per node);
//   distributed  GGᵀ assembled in distributed form (each rank the rows of its block of
//                subdomains, from the columns of B that touch them) into an Epetra matrix and
//                factorized and solved by MUMPS through Trilinos Amesos.
// Prints one CSV row per size and method: ranks, subdomains, coarse unknowns (6 N³), entries of
// G, setup seconds (assembly and factorization), solve seconds (one solve), and the peak
// resident memory of rank 0 [MiB] after that size (VmHWM: monotone over the run; give one method
// and increasing sizes to read it per size), the largest peak of the other ranks without the
// shared factor they map (VmHWM minus its bytes: what the rank holds of its own), and ‖(GGᵀ)⁻¹b‖
// for a fixed b (the same for all methods). Run by benchmarks/coarse_problem.py
// (doc/performance.md).

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_solver.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/lac/trilinos_vector.h>

#include <feticontact/feti/coarse_problem.h>
#include <feticontact/feti/dual_space.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace dealii;
using namespace FetiContact;

namespace
{
  using Clock = std::chrono::steady_clock;

  double
  seconds_since(const Clock::time_point start)
  {
    return std::chrono::duration<double>(Clock::now() - start).count();
  }

  double
  median(std::vector<double> v)
  {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  }

  /** Peak resident memory of this process [MiB] (VmHWM of /proc/self/status). */
  double
  peak_mib()
  {
    std::ifstream status("/proc/self/status");
    std::string   line;
    while (std::getline(status, line))
      if (line.rfind("VmHWM:", 0) == 0)
        return std::stod(line.substr(6)) / 1024;
    return 0;
  }

  /**
   * One column of G: the point p on the boundary of subdomain a (and b, if it glues two
   * subdomains; then the row is u_a − u_b) and the displacement component c.
   */
  struct Column
  {
    unsigned int          a, b;
    bool                  glue;
    std::array<double, 3> p;
    unsigned int          component;
  };

  /**
   * The columns of G of the cube of n³ unit subdomains, each generated once; @p touches limits
   * them to the columns that touch subdomains for which it holds.
   */
  template <typename Predicate>
  std::vector<Column>
  columns(const unsigned int n, const Predicate &touches)
  {
    std::vector<Column> result;
    const auto          index = [n](const int i, const int j, const int k) {
      return static_cast<unsigned int>(i + n * (j + n * k));
    };
    const auto add_point = [&](const unsigned int           a,
                               const unsigned int           b,
                               const bool                   glue,
                               const std::array<double, 3> &p) {
      if (!touches(a) && !(glue && touches(b)))
        return;
      for (unsigned int c = 0; c < 3; ++c)
        result.push_back(Column{a, b, glue, p, c});
    };
    const int m = static_cast<int>(n);
    for (int k = 0; k < m; ++k)
      for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i)
          {
            const unsigned int a = index(i, j, k);
            // Neighbours in the positive directions (each pair once): faces, edges, corners.
            for (int dk = 0; dk <= 1; ++dk)
              for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di)
                  {
                    if (dk == 0 && (dj < 0 || (dj == 0 && di <= 0)))
                      continue;
                    const int ii = i + di, jj = j + dj, kk = k + dk;
                    if (ii < 0 || jj < 0 || ii >= m || jj >= m || kk >= m)
                      continue;
                    const unsigned int b       = index(ii, jj, kk);
                    const int          n_shift = std::abs(di) + std::abs(dj) + std::abs(dk);
                    // The shared point set: the centre of the shared face/edge/corner,
                    // and on a face three more points around it.
                    const std::array<double, 3> centre{
                      {i + 0.5 + 0.5 * di, j + 0.5 + 0.5 * dj, k + 0.5 + 0.5 * dk}};
                    add_point(a, b, true, centre);
                    if (n_shift == 1)
                      for (const double s : {-0.25, 0.25})
                        for (const double t : {-0.25, 0.25})
                          {
                            if (s < 0 && t < 0)
                              continue;
                            auto p = centre;
                            // The two in-face directions.
                            const unsigned int normal = di != 0 ? 0 : dj != 0 ? 1 : 2;
                            p[(normal + 1) % 3] += s;
                            p[(normal + 2) % 3] += t;
                            add_point(a, b, true, p);
                          }
                  }
            if (i == 0)
              for (const double s : {-0.25, 0.25})
                for (const double t : {-0.25, 0.25})
                  add_point(a, a, false, {{0.0, j + 0.5 + s, k + 0.5 + t}});
          }
    return result;
  }

  /** The six rigid modes of unit subdomain @p s at @p p, component @p c. */
  std::array<double, 6>
  modes(const unsigned int           n,
        const unsigned int           s,
        const std::array<double, 3> &p,
        const unsigned int           c)
  {
    const std::array<double, 3> centre{{s % n + 0.5, (s / n) % n + 0.5, s / (n * n) + 0.5}};
    const std::array<double, 3> x{{p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]}};
    std::array<double, 6>       r{};
    r[c] = 1;
    // e_q × x, component c, for q = 0, 1, 2.
    for (unsigned int q = 0; q < 3; ++q)
      {
        std::array<double, 3> e{};
        e[q]                                 = 1;
        const std::array<double, 3> rotation = {
          {e[1] * x[2] - e[2] * x[1], e[2] * x[0] - e[0] * x[2], e[0] * x[1] - e[1] * x[0]}};
        r[3 + q] = rotation[c];
      }
    return r;
  }

  /** The entries (mode, value) of one column of G. */
  std::vector<std::pair<unsigned int, double>>
  column_entries(const unsigned int n, const Column &col)
  {
    std::vector<std::pair<unsigned int, double>> e;
    const auto                                   ra = modes(n, col.a, col.p, col.component);
    for (unsigned int q = 0; q < 6; ++q)
      if (ra[q] != 0)
        e.emplace_back(6 * col.a + q, ra[q]);
    if (col.glue)
      {
        const auto rb = modes(n, col.b, col.p, col.component);
        for (unsigned int q = 0; q < 6; ++q)
          if (rb[q] != 0)
            e.emplace_back(6 * col.b + q, -rb[q]);
      }
    return e;
  }

  struct Row
  {
    std::string  method;
    unsigned int ranks, subdomains, unknowns;
    double       g_entries, setup, solve, peak, peak_others, solution_norm;
  };

  /** The largest VmHWM of ranks 1, 2, … less @p shared_bytes each maps [MiB] (0 on one rank). */
  double
  peak_of_others(const MPI_Comm comm, const std::size_t shared_bytes)
  {
    const std::vector<double> own =
      Utilities::MPI::all_gather(comm, peak_mib() - shared_bytes / (1024.0 * 1024.0));
    return own.size() > 1 ? *std::max_element(own.begin() + 1, own.end()) : 0.0;
  }

  /**
   * G by the columns that touch each rank's subdomains, GGᵀ gathered and factorized by CHOLMOD
   * (CoarseProblem) on every rank or once per node (@p storage).
   */
  Row
  replicated(const MPI_Comm                     comm,
             const unsigned int                 n,
             const unsigned int                 repeats,
             const CoarseProblem::FactorStorage storage)
  {
    const unsigned int rank = Utilities::MPI::this_mpi_process(comm);
    const unsigned int size = Utilities::MPI::n_mpi_processes(comm);
    const unsigned int N    = n * n * n;
    // A rank owns a contiguous block of subdomains and the columns whose first subdomain is in
    // it; the columns are numbered in the order columns() makes them (by first subdomain).
    const auto                owner_of = [&](const unsigned int s) { return s * size / N; };
    const auto                mine     = [&](const unsigned int s) { return owner_of(s) == rank; };
    const auto                all      = columns(n, [](const unsigned int) { return true; });
    std::vector<unsigned int> owned, chunk, ghosts;
    std::vector<int>          ghost_owner;
    std::vector<CoarseProblem::Entry> entries;
    unsigned int                      first_subdomain = N, end_subdomain = 0;
    for (unsigned int s = 0; s < N; ++s)
      if (mine(s))
        {
          first_subdomain = std::min(first_subdomain, s);
          end_subdomain   = s + 1;
        }
    for (unsigned int j = 0; j < all.size(); ++j)
      {
        const Column &c = all[j];
        if (mine(c.a))
          {
            owned.push_back(j);
            chunk.push_back(c.a);
          }
        else if (c.glue && mine(c.b))
          {
            ghosts.push_back(j);
            ghost_owner.push_back(owner_of(c.a));
          }
        if (mine(c.a) || (c.glue && mine(c.b)))
          {
            for (const auto &[mode, value] : column_entries(n, c))
              entries.push_back({mode, j, value});
          }
      }
    const unsigned int total = all.size();
    const DualSpace    distribution(comm, owned, chunk, ghosts, ghost_owner, total);
    if (first_subdomain > end_subdomain)
      first_subdomain = end_subdomain;
    // The ranks' mode ranges must follow each other: a rank without subdomains starts where the
    // previous one ends.
    unsigned int first_mode = 0, n_own_modes = 6 * (end_subdomain - first_subdomain);
    MPI_Exscan(&n_own_modes, &first_mode, 1, MPI_UNSIGNED, MPI_SUM, comm);
    if (rank == 0)
      first_mode = 0;
    std::vector<double> setup, solve;
    double              norm        = 0;
    double              own_entries = 0;
    for (const auto &e : entries)
      own_entries += mine(all[e.column].a);
    const double g_entries = Utilities::MPI::sum(own_entries, comm);
    std::size_t  shared    = 0;
    for (unsigned int r = 0; r < repeats; ++r)
      {
        CoarseProblem coarse(storage);
        MPI_Barrier(comm);
        auto start = Clock::now();
        coarse.initialize(
          distribution, entries, 6 * N, total, first_mode, first_mode + n_own_modes);
        MPI_Barrier(comm);
        setup.push_back(seconds_since(start));
        Vector<double> x(6 * N);
        for (unsigned int i = 0; i < x.size(); ++i)
          x[i] = 1.0 + (i % 7);
        MPI_Barrier(comm);
        start = Clock::now();
        coarse.solve_GGt(x);
        MPI_Barrier(comm);
        solve.push_back(seconds_since(start));
        norm   = x.l2_norm();
        shared = coarse.shared_factor_bytes();
      }
    return {storage == CoarseProblem::FactorStorage::per_rank ? "replicated" : "per-node",
            size,
            N,
            6 * N,
            g_entries,
            median(setup),
            median(solve),
            peak_mib(),
            peak_of_others(comm, shared),
            norm};
  }

  /** GGᵀ assembled by rows on the ranks, factorized and solved by MUMPS (Amesos). */
  Row
  distributed(const MPI_Comm comm, const unsigned int n, const unsigned int repeats)
  {
    const unsigned int rank     = Utilities::MPI::this_mpi_process(comm);
    const unsigned int size     = Utilities::MPI::n_mpi_processes(comm);
    const unsigned int N        = n * n * n;
    const auto         first_of = [&](const unsigned int r) { return (r * N + size - 1) / size; };
    const auto         owner    = [&](const unsigned int s) {
      unsigned int r = s * size / N;
      while (r + 1 < size && first_of(r + 1) <= s)
        ++r;
      while (r > 0 && first_of(r) > s)
        --r;
      return r;
    };
    IndexSet owned(6 * N);
    owned.add_range(6 * first_of(rank), 6 * first_of(rank + 1));
    owned.compress();
    const auto cols        = columns(n, [&](const unsigned int s) { return owner(s) == rank; });
    double     own_entries = 0;
    for (const auto &c : cols)
      if (owner(c.a) == rank)
        own_entries += column_entries(n, c).size();
    const double        g_entries = Utilities::MPI::sum(own_entries, comm);
    std::vector<double> setup, solve;
    double              norm = 0;
    for (unsigned int r = 0; r < repeats; ++r)
      {
        MPI_Barrier(comm);
        auto start = Clock::now();
        // Each column adds g gᵀ; this rank keeps the rows it owns.
        std::map<std::pair<unsigned int, unsigned int>, double> local;
        for (const auto &c : cols)
          {
            const auto e = column_entries(n, c);
            for (const auto &[i, gi] : e)
              if (owned.is_element(i))
                for (const auto &[j, gj] : e)
                  local[{i, j}] += gi * gj;
          }
        TrilinosWrappers::SparsityPattern sparsity(owned, owned, comm);
        for (const auto &[ij, v] : local)
          sparsity.add(ij.first, ij.second);
        sparsity.compress();
        TrilinosWrappers::SparseMatrix GGt;
        GGt.reinit(sparsity);
        for (const auto &[ij, v] : local)
          GGt.set(ij.first, ij.second, v);
        GGt.compress(VectorOperation::insert);
        SolverControl                                  control(1, 0);
        TrilinosWrappers::SolverDirect::AdditionalData data(false, "Amesos_Mumps");
        TrilinosWrappers::SolverDirect                 solver(control, data);
        solver.initialize(GGt);
        MPI_Barrier(comm);
        setup.push_back(seconds_since(start));
        TrilinosWrappers::MPI::Vector b(owned, comm), x(owned, comm);
        for (const auto i : owned)
          b[i] = 1.0 + (i % 7);
        b.compress(VectorOperation::insert);
        MPI_Barrier(comm);
        start = Clock::now();
        solver.solve(x, b);
        MPI_Barrier(comm);
        solve.push_back(seconds_since(start));
        norm = x.l2_norm();
      }
    return {"distributed",
            size,
            N,
            6 * N,
            g_entries,
            median(setup),
            median(solve),
            peak_mib(),
            peak_of_others(comm, 0),
            norm};
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                   comm = MPI_COMM_WORLD;
  std::vector<unsigned int>        sizes{4, 8, 12, 16};
  unsigned int                     repeats = 3;
  std::vector<std::string>         methods{"replicated", "per-node", "distributed"};
  for (int i = 1; i < argc; ++i)
    {
      const std::string option = argv[i];
      if (option == "--sizes" && i + 1 < argc)
        {
          sizes.clear();
          std::istringstream list(argv[++i]);
          std::string        item;
          while (std::getline(list, item, ','))
            sizes.push_back(std::stoi(item));
        }
      else if (option == "--repeats" && i + 1 < argc)
        repeats = std::stoi(argv[++i]);
      else if (option == "--methods" && i + 1 < argc)
        {
          methods.clear();
          std::istringstream list(argv[++i]);
          std::string        item;
          while (std::getline(list, item, ','))
            methods.push_back(item);
        }
      else
        {
          std::cerr << "unknown option " << option << std::endl;
          return 1;
        }
    }
  const bool rank_0 = Utilities::MPI::this_mpi_process(comm) == 0;
  if (rank_0)
    std::cout << "method,ranks,subdomains,coarse_unknowns,G_entries,setup_seconds,"
                 "solve_seconds,peak_mib_rank0,peak_mib_others,solution_norm\n";
  const auto print = [&](const Row &r) {
    if (rank_0)
      std::cout << r.method << ',' << r.ranks << ',' << r.subdomains << ',' << r.unknowns << ','
                << r.g_entries << ',' << r.setup << ',' << r.solve << ',' << r.peak << ','
                << r.peak_others << ',' << r.solution_norm << std::endl;
  };
  for (const std::string &method : methods)
    for (const unsigned int n : sizes)
      if (method == "replicated")
        print(replicated(comm, n, repeats, CoarseProblem::FactorStorage::per_rank));
      else if (method == "per-node")
        print(replicated(comm, n, repeats, CoarseProblem::FactorStorage::per_node));
      else if (method == "distributed")
        print(distributed(comm, n, repeats));
      else
        {
          std::cerr << "unknown method " << method << std::endl;
          return 1;
        }
  return 0;
}
