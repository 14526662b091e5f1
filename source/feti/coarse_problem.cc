#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/base/mpi_tools.h>
#include <feticontact/feti/coarse_problem.h>
#include <feticontact/feti/dual_space.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

namespace FetiContact
{
  namespace
  {
    /**
     * ‖Gλ₀ − e‖ ≤ this × ‖e‖ accepts a particular solution from a subset of the columns of G:
     * far above the rounding of a subset that restrains every mode (measured 1e-16 … 1e-14),
     * far below the misfit of one that does not (measured 1e-2 and more).
     */
    constexpr double particular_solution_tolerance = 1e-10;
  } // namespace

  using namespace dealii;

  CoarseProblem::CoarseProblem(const FactorStorage storage)
    : storage(storage)
  {}

  CoarseProblem::~CoarseProblem()
  {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (finalized)
      return;
    for (MPI_Comm *c : {&node, &leaders})
      if (*c != MPI_COMM_NULL)
        MPI_Comm_free(c);
  }

  void
  CoarseProblem::set_up_node(const MPI_Comm comm)
  {
    if (storage != FactorStorage::per_node || node != MPI_COMM_NULL)
      return;
    int rank = 0, node_rank = 0, node_size = 1;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node);
    MPI_Comm_rank(node, &node_rank);
    MPI_Comm_size(node, &node_size);
    // Collective on comm: every node decides alike only with the same answer everywhere.
    if (Utilities::MPI::max(node_size, comm) == 1)
      {
        MPI_Comm_free(&node);
        return;
      }
    MPI_Comm_split(comm, node_rank == 0 ? 0 : MPI_UNDEFINED, rank, &leaders);
  }

  bool
  CoarseProblem::on_factorizing_rank(const std::function<bool()> &work) const
  {
    if (node == MPI_COMM_NULL)
      return work();
    // The first character: '0' work() returned false, '1' true, 'I' InputError, 'E' another
    // exception, followed by its message.
    std::string outcome = "0";
    if (factorizes())
      try
        {
          outcome = work() ? "1" : "0";
        }
      catch (const InputError &e)
        {
          outcome = std::string("I") + e.what();
        }
      catch (const std::exception &e)
        {
          outcome = std::string("E") + e.what();
        }
    outcome = Utilities::MPI::broadcast(node, outcome, 0);
    if (outcome[0] == 'I')
      throw InputError(outcome.substr(1));
    if (outcome[0] == 'E')
      throw std::runtime_error(outcome.substr(1));
    return outcome[0] == '1';
  }

  void
  CoarseProblem::share(CholmodSolver &solver) const
  {
    if (node != MPI_COMM_NULL)
      solver.share_factor(node);
  }

  void
  CoarseProblem::factorize_GGt(const SparseMatrix<double> &M)
  {
    // The bodies' supports and contact nodes are checked before; what is left to name.
    const std::string not_held_causes =
      ": a subdomain is joined to the rest of its body only at a vertex or along an edge (a "
      "decomposition of a thin part), or a body is held by contact rows that restrain only some "
      "of its rigid motions (a single contact node, contact nodes on one line).";
    on_factorizing_rank([&]() {
      for (unsigned int r = 0; r < n_rows; ++r)
        require(M.diag_element(r) > 0,
                "The coarse problem is singular: rigid body mode " + std::to_string(r) +
                  " of a floating subdomain is restrained by no constraint" + not_held_causes);
      try
        {
          GGt.factorize(M);
        }
      catch (const InputError &)
        {
          throw InputError("The coarse problem GGᵀ is singular: some rigid motion of a floating "
                           "subdomain is restrained by no constraint" +
                           not_held_causes);
        }
      const double rcond = GGt.reciprocal_condition_estimate();
      require(rcond > 1e-13,
              "The coarse problem GGᵀ is numerically singular (reciprocal condition estimate " +
                InputParsing::number_text(rcond) + ")" + not_held_causes);
      return true;
    });
    share(GGt);
  }

  void
  CoarseProblem::initialize(const DualSpace   &d,
                            std::vector<Entry> relevant_entries,
                            const unsigned int n_modes,
                            const unsigned int n_columns,
                            const unsigned int first_mode,
                            const unsigned int end_mode)
  {
    n_rows = n_modes;
    n_cols = n_columns;
    work.reinit(n_rows);
    // The relevant columns by increasing column, each by increasing mode (the order in which
    // assemble_GGt() adds the terms of GGᵀ and add_Gt those of Gᵀy). Two entries of one mode in
    // one column (a row of B with two terms in one subdomain: mortar rows) keep the order in
    // which the subdomain's rank made them, the same on any number of ranks.
    std::stable_sort(relevant_entries.begin(),
                     relevant_entries.end(),
                     [](const Entry &a, const Entry &b) {
                       return a.column < b.column || (a.column == b.column && a.mode < b.mode);
                     });
    relevant_column.clear();
    relevant_start.assign(1, 0);
    relevant_mode.clear();
    relevant_value.clear();
    for (const Entry &e : relevant_entries)
      {
        if (relevant_column.empty() || relevant_column.back() != e.column)
          {
            relevant_column.push_back(e.column);
            relevant_start.push_back(relevant_start.back());
          }
        ++relevant_start.back();
        relevant_mode.push_back(e.mode);
        relevant_value.push_back(e.value);
      }
    // G by the rows of this rank's modes, columns increasing (CSR over all modes: the other
    // modes' rows are empty), for distribute().
    row_start.assign(n_rows + 1, 0);
    for (const Entry &e : relevant_entries)
      if (e.mode >= first_mode && e.mode < end_mode)
        ++row_start[e.mode + 1];
    for (unsigned int r = 0; r < n_rows; ++r)
      row_start[r + 1] += row_start[r];
    column.resize(row_start.back());
    value.resize(row_start.back());
    std::vector<unsigned int> next(row_start.begin(), row_start.end() - 1);
    for (const Entry &e : relevant_entries)
      if (e.mode >= first_mode && e.mode < end_mode)
        {
          column[next[e.mode]]  = e.column;
          value[next[e.mode]++] = e.value;
        }
    distribute(d, first_mode, end_mode);
    if (n_rows == 0)
      return;
    set_up_node(d.partitioner()->get_mpi_communicator());
    SparsityPattern      sp;
    SparseMatrix<double> M;
    assemble_GGt([](const unsigned int) { return true; }, sp, M);
    factorize_GGt(M);
  }

  void
  CoarseProblem::assemble_GGt(const std::function<bool(unsigned int)> &use_column,
                              SparsityPattern                         &sparsity,
                              SparseMatrix<double>                    &M) const
  {
    // (G_S G_Sᵀ)_ab = Σ_{d ∈ S} G_ad G_bd for this rank's modes a, the terms by increasing column
    // d. Then every rank's rows to the ranks that factorize.
    std::map<std::pair<unsigned int, unsigned int>, double> own;
    for (unsigned int j = 0; j + 1 < relevant_start.size(); ++j)
      if (use_column(relevant_column[j]))
        for (unsigned int k = relevant_start[j]; k < relevant_start[j + 1]; ++k)
          if (own_modes.begin() <= relevant_mode[k] && relevant_mode[k] < own_modes.end())
            for (unsigned int l = relevant_start[j]; l < relevant_start[j + 1]; ++l)
              own[{relevant_mode[k], relevant_mode[l]}] += relevant_value[k] * relevant_value[l];
    std::vector<Entry> local;
    local.reserve(own.size());
    for (const auto &[ab, v] : own)
      local.push_back({ab.first, ab.second, v});
    std::vector<Entry> all;
    if (node == MPI_COMM_NULL)
      all = MPITools::all_gather(space->partitioner()->get_mpi_communicator(), local);
    else
      {
        // To the first rank of every node: M is assembled and factorized there only.
        all = MPITools::gather(node, local, 0);
        if (!factorizes())
          return;
        all = MPITools::all_gather(leaders, all);
      }
    DynamicSparsityPattern dsp(n_rows);
    for (unsigned int r = 0; r < n_rows; ++r)
      dsp.add(r, r);
    for (const Entry &e : all)
      dsp.add(e.mode, e.column);
    sparsity.copy_from(dsp);
    M.reinit(sparsity);
    for (const Entry &e : all)
      M.set(e.mode, e.column, e.value);
  }

  unsigned int
  CoarseProblem::tiers_present(const std::function<unsigned int(unsigned int)> &tier) const
  {
    unsigned int mask = 0;
    for (const unsigned int c : space->partitioner()->owned_keys())
      mask |= 1u << tier(c);
    MPI_Allreduce(
      MPI_IN_PLACE, &mask, 1, MPI_UNSIGNED, MPI_BOR, space->partitioner()->get_mpi_communicator());
    return mask;
  }

  void
  CoarseProblem::distribute(const DualSpace   &d,
                            const unsigned int first_mode,
                            const unsigned int end_mode)
  {
    space       = &d;
    int n_ranks = 1;
    MPI_Comm_size(d.partitioner()->get_mpi_communicator(), &n_ranks);
    std::vector<unsigned int> firsts(n_ranks + 1, n_rows);
    MPI_Allgather(&first_mode,
                  1,
                  MPI_UNSIGNED,
                  firsts.data(),
                  1,
                  MPI_UNSIGNED,
                  d.partitioner()->get_mpi_communicator());
    own_modes = BlockPartition(d.partitioner()->get_mpi_communicator(), firsts);
    AssertThrow(own_modes.begin() == first_mode && own_modes.end() == end_mode,
                ExcMessage(
                  "CoarseProblem::distribute: the ranks' modes do not follow each other."));
    own_mode_column.clear();
    for (unsigned int k = row_start[first_mode]; k < row_start[end_mode]; ++k)
      own_mode_column.push_back(d.local_index(column[k]));
    // G by the owned columns, modes increasing within each (as in add_Gt).
    const auto &own = d.partitioner()->owned_keys();
    // From the relevant columns, which include the owned ones.
    own_column_start.assign(1, 0);
    own_column_mode.clear();
    own_column_value.clear();
    for (const unsigned int c : own)
      {
        const auto it = std::lower_bound(relevant_column.begin(), relevant_column.end(), c);
        if (it != relevant_column.end() && *it == c)
          {
            const unsigned int j = it - relevant_column.begin();
            own_column_mode.insert(own_column_mode.end(),
                                   relevant_mode.begin() + relevant_start[j],
                                   relevant_mode.begin() + relevant_start[j + 1]);
            own_column_value.insert(own_column_value.end(),
                                    relevant_value.begin() + relevant_start[j],
                                    relevant_value.begin() + relevant_start[j + 1]);
          }
        own_column_start.push_back(own_column_mode.size());
      }
  }

  void
  CoarseProblem::apply_G(const DualVector &x, Vector<double> &y) const
  {
    Assert(space, ExcMessage("CoarseProblem: distribute() first."));
    if (y.size() != n_rows)
      y.reinit(n_rows, true);
    x.update_ghost_values();
    const unsigned int first = row_start[own_modes.begin()];
    for (unsigned int r = own_modes.begin(); r < own_modes.end(); ++r)
      {
        double s = 0;
        for (unsigned int k = row_start[r]; k < row_start[r + 1]; ++k)
          s += value[k] * x.local_element(own_mode_column[k - first]);
        y[r] = s;
      }
    x.zero_out_ghost_values();
    own_modes.gather(y.begin());
  }

  void
  CoarseProblem::apply_Gt(const Vector<double> &x, DualVector &y) const
  {
    add_Gt(x, false, y);
  }

  void
  CoarseProblem::add_Gt(const Vector<double> &x, const bool add, DualVector &y) const
  {
    Assert(space, ExcMessage("CoarseProblem: distribute() first."));
    Assert(!add || y.get_partitioner() == space->partitioner(), ExcInternalError());
    if (y.get_partitioner() != space->partitioner())
      y.reinit(space->partitioner());
    for (unsigned int i = 0; i < y.locally_owned_size(); ++i)
      {
        double s = add ? y.local_element(i) : 0.;
        for (unsigned int k = own_column_start[i]; k < own_column_start[i + 1]; ++k)
          s += own_column_value[k] * x[own_column_mode[k]];
        y.local_element(i) = s;
      }
  }

  void
  CoarseProblem::apply_G_orthonormal(const DualVector &x, Vector<double> &y) const
  {
    apply_G(x, y);
    if (n_rows > 0)
      GGt.solve_half(y, false);
  }

  void
  CoarseProblem::apply_Gt_orthonormal(const Vector<double> &x, DualVector &y) const
  {
    Vector<double> z(x);
    if (n_rows > 0)
      GGt.solve_half(z, true);
    apply_Gt(z, y);
  }

  Vector<double>
  CoarseProblem::multiplier_from_orthonormal(const Vector<double> &mu_tilde) const
  {
    Vector<double> mu(mu_tilde);
    if (n_rows > 0)
      GGt.solve_half(mu, true);
    return mu;
  }

  void
  CoarseProblem::apply_orthonormalizing_factor(Vector<double> &v, const bool transpose) const
  {
    if (n_rows > 0)
      GGt.solve_half(v, transpose);
  }

  Vector<double>
  CoarseProblem::orthonormal_rhs(const Vector<double> &e) const
  {
    Vector<double> r(e);
    if (n_rows > 0)
      GGt.solve_half(r, false);
    return r;
  }

  void
  CoarseProblem::solve_GGt(Vector<double> &x) const
  {
    if (n_rows > 0)
      GGt.solve(x);
  }

  void
  CoarseProblem::project(DualVector &x) const
  {
    if (n_rows == 0)
      return;
    apply_G(x, work);
    GGt.solve(work);
    // x_c − Σ_r G_rc w_r as x_c + Σ_r G_rc (−w_r): the same numbers.
    work *= -1.;
    add_Gt(work, true, x);
  }

  void
  CoarseProblem::least_norm_solution(const Vector<double> &e, DualVector &lambda) const
  {
    Vector<double> mu(e);
    solve_GGt(mu);
    apply_Gt(mu, lambda);
  }

  void
  CoarseProblem::particular_solution(const Vector<double>                            &e,
                                     const std::function<unsigned int(unsigned int)> &tier,
                                     DualVector                                      &lambda) const
  {
    Assert(space, ExcMessage("CoarseProblem: distribute() first."));
    lambda.reinit(space->partitioner());
    const double e_norm = e.l2_norm();
    if (n_rows == 0 || e_norm == 0)
      return;
    const unsigned int tiers = tiers_present(tier);
    // The last tier takes every column: the factorization of GGᵀ that exists already.
    for (unsigned int t = 0; (tiers >> (t + 1)) != 0; ++t)
      {
        if (!(tiers & (1u << t)))
          continue;
        const auto           use_column = [&](const unsigned int c) { return tier(c) <= t; };
        SparsityPattern      sp;
        SparseMatrix<double> M;
        assemble_GGt(use_column, sp, M);
        CholmodSolver factor;
        const bool    usable = on_factorizing_rank([&]() {
          for (unsigned int r = 0; r < n_rows; ++r)
            if (!(M.diag_element(r) > 0))
              return false;
          try
            {
              factor.factorize(M);
            }
          catch (const InputError &)
            {
              return false;
            }
          // The same bound as for GGᵀ itself (initialize): a subset that restrains the modes
          // only nearly would give a λ₀ far larger than the least-norm one.
          return factor.reciprocal_condition_estimate() > 1e-13;
        });
        if (!usable)
          continue;
        // λ = G_tᵀ(G_t G_tᵀ)⁻¹ r, accumulated over one step of iterative refinement; every
        // column's terms by increasing mode.
        lambda = 0;
        Vector<double> r(e), G_lambda;
        for (unsigned int step = 0; step < 2; ++step)
          {
            // Two solves with a factor made for them: on the factorizing rank, then sent to the
            // node's other ranks (cheaper than sharing the factor).
            if (factorizes())
              factor.solve(r);
            if (node != MPI_COMM_NULL)
              MPI_Bcast(r.begin(), r.size(), MPI_DOUBLE, 0, node);
            for (unsigned int i = 0; i < lambda.locally_owned_size(); ++i)
              if (use_column(space->row(i)))
                for (unsigned int k = own_column_start[i]; k < own_column_start[i + 1]; ++k)
                  lambda.local_element(i) += own_column_value[k] * r[own_column_mode[k]];
            apply_G(lambda, G_lambda);
            r = e;
            r -= G_lambda;
          }
        // The estimate of the condition number bounds the pivots, not the rank: G_t G_tᵀ that
        // is singular in exact arithmetic (a rigid motion restrained only by the rows of the
        // higher tiers, e.g. a body held along x by friction alone, cut into many subdomains)
        // can pass it on rounding, and its "solution" then misses Gλ = e by far. The residual
        // decides.
        if (r.l2_norm() <= particular_solution_tolerance * e_norm)
          return;
      }
    least_norm_solution(e, lambda);
  }

  double
  CoarseProblem::restore_feasibility(DualVector &lambda, const Vector<double> &e) const
  {
    if (n_rows == 0)
      return 0;
    Vector<double> r(e), Gl;
    apply_G(lambda, Gl);
    r -= Gl;
    const double norm_e = e.l2_norm();
    const double misfit = norm_e > 0 ? r.l2_norm() / norm_e : r.l2_norm();
    // λ + Gᵀ(GGᵀ)⁻¹r.
    solve_GGt(r);
    DualVector correction;
    correction.reinit(lambda);
    apply_Gt(r, correction);
    lambda += correction;
    return misfit;
  }

  Vector<double>
  CoarseProblem::coarse_coefficients(const DualVector &x) const
  {
    Vector<double> alpha;
    apply_G(x, alpha);
    solve_GGt(alpha);
    return alpha;
  }
} // namespace FetiContact
