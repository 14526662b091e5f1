#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/base/mpi_tools.h>
#include <feticontact/feti/coarse_problem.h>
#include <feticontact/feti/dual_distribution.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <type_traits>

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
  CoarseProblem::initialize(const MPI_Comm            comm,
                            const std::vector<Entry> &local_entries,
                            const unsigned int        n_modes,
                            const unsigned int        n_columns)
  {
    n_rows       = n_modes;
    n_cols       = n_columns;
    auto entries = MPITools::all_gather(comm, local_entries);
    std::sort(entries.begin(), entries.end(), [](const Entry &a, const Entry &b) {
      return a.mode < b.mode || (a.mode == b.mode && a.column < b.column);
    });
    row_start.assign(n_rows + 1, 0);
    column.clear();
    value.clear();
    for (const auto &e : entries)
      {
        ++row_start[e.mode + 1];
        column.push_back(e.column);
        value.push_back(e.value);
      }
    for (unsigned int r = 0; r < n_rows; ++r)
      row_start[r + 1] += row_start[r];
    work.reinit(n_rows);

    // The products with G and Gᵀ are split among the ranks: G x by blocks of modes (rows of G),
    // Gᵀ x by blocks of dual unknowns (columns of G), each block with about equal numbers of
    // entries. For the columns of its block a rank keeps G by columns, every column's entries in
    // the order of increasing mode, so that (Gᵀx)_c is summed in the same order as by rows.
    mode_blocks = BlockPartition::balanced(comm, row_start);
    std::vector<unsigned int> entries_before_column(n_cols + 1, 0);
    for (const unsigned int c : column)
      ++entries_before_column[c + 1];
    for (unsigned int c = 0; c < n_cols; ++c)
      entries_before_column[c + 1] += entries_before_column[c];
    column_blocks                      = BlockPartition::balanced(comm, entries_before_column);
    const unsigned int first_column    = column_blocks.begin();
    const unsigned int n_block_columns = column_blocks.end() - first_column;
    block_column_start.assign(n_block_columns + 1, 0);
    for (unsigned int c = 0; c <= n_block_columns; ++c)
      block_column_start[c] =
        entries_before_column[first_column + c] - entries_before_column[first_column];
    block_column_mode.resize(block_column_start.back());
    block_column_value.resize(block_column_start.back());
    std::vector<unsigned int> next(block_column_start.begin(), block_column_start.end() - 1);
    for (unsigned int r = 0; r < n_rows; ++r)
      for (unsigned int k = row_start[r]; k < row_start[r + 1]; ++k)
        if (column[k] >= first_column && column[k] < column_blocks.end())
          {
            const unsigned int j  = next[column[k] - first_column]++;
            block_column_mode[j]  = r;
            block_column_value[j] = value[k];
          }
    if (n_rows == 0)
      return;

    set_up_node(comm);
    SparsityPattern      sp;
    SparseMatrix<double> M;
    assemble_GGt([](const unsigned int) { return true; }, sp, M);
    factorize_GGt(M);
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
  CoarseProblem::initialize_distributed(const DualDistribution &d,
                                        std::vector<Entry>      relevant_entries,
                                        const unsigned int      n_modes,
                                        const unsigned int      n_columns,
                                        const unsigned int      first_mode,
                                        const unsigned int      end_mode)
  {
    n_rows           = n_modes;
    n_cols           = n_columns;
    distributed_only = true;
    work.reinit(n_rows);
    // The relevant columns by increasing column, each by increasing mode (the order in which
    // initialize() adds the terms of GGᵀ and add_Gt those of Gᵀy). Two entries of one mode in
    // one column (a row of B with two terms in one subdomain: mortar rows) keep the order in
    // which the subdomain's rank made them, the same on any number of ranks; initialize() leaves
    // them as std::sort does, so there the two forms of G round differently.
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
    set_up_node(d.layout()->comm);
    SparsityPattern      sp;
    SparseMatrix<double> M;
    assemble_GGt_distributed([](const unsigned int) { return true; }, sp, M);
    factorize_GGt(M);
  }

  void
  CoarseProblem::assemble_GGt_distributed(const std::function<bool(unsigned int)> &use_column,
                                          SparsityPattern                         &sparsity,
                                          SparseMatrix<double>                    &M) const
  {
    // (G_S G_Sᵀ)_ab for this rank's modes a, the terms by increasing column d ∈ S as in
    // assemble_GGt(): the same numbers. Then every rank's rows to every rank.
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
      all = MPITools::all_gather(distribution->layout()->comm, local);
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
    if (!distributed_only)
      {
        for (unsigned int c = 0; c < n_cols; ++c)
          mask |= 1u << tier(c);
        return mask;
      }
    for (const unsigned int c : distribution->layout()->global_index)
      mask |= 1u << tier(c);
    MPI_Allreduce(MPI_IN_PLACE, &mask, 1, MPI_UNSIGNED, MPI_BOR, distribution->layout()->comm);
    return mask;
  }

  void
  CoarseProblem::assemble_GGt(const std::function<bool(unsigned int)> &use_column,
                              SparsityPattern                         &sparsity,
                              SparseMatrix<double>                    &M) const
  {
    if (!factorizes())
      return;
    // (G_S G_Sᵀ)_ab = Σ_{d ∈ S} G_ad G_bd, from the columns of G.
    std::vector<std::vector<std::pair<unsigned int, double>>> by_column(n_cols);
    for (unsigned int r = 0; r < n_rows; ++r)
      for (unsigned int k = row_start[r]; k < row_start[r + 1]; ++k)
        if (use_column(column[k]))
          by_column[column[k]].emplace_back(r, value[k]);
    DynamicSparsityPattern dsp(n_rows);
    for (unsigned int r = 0; r < n_rows; ++r)
      dsp.add(r, r);
    for (const auto &col : by_column)
      for (const auto &[a, va] : col)
        for (const auto &[b, vb] : col)
          dsp.add(a, b);
    sparsity.copy_from(dsp);
    M.reinit(sparsity);
    for (const auto &col : by_column)
      for (const auto &[a, va] : col)
        for (const auto &[b, vb] : col)
          M.add(a, b, va * vb);
  }

  void
  CoarseProblem::apply_G(const Vector<double> &x, Vector<double> &y) const
  {
    AssertThrow(!distributed_only,
                ExcMessage("CoarseProblem: G is distributed; use distributed dual vectors."));
    if (y.size() != n_rows)
      y.reinit(n_rows, true);
    for (unsigned int r = mode_blocks.begin(); r < mode_blocks.end(); ++r)
      {
        double s = 0;
        for (unsigned int k = row_start[r]; k < row_start[r + 1]; ++k)
          s += value[k] * x[column[k]];
        y[r] = s;
      }
    mode_blocks.gather(y.begin());
  }

  void
  CoarseProblem::distribute(const DualDistribution &d,
                            const unsigned int      first_mode,
                            const unsigned int      end_mode)
  {
    distribution = &d;
    int n_ranks  = 1;
    MPI_Comm_size(d.layout()->comm, &n_ranks);
    std::vector<unsigned int> firsts(n_ranks + 1, n_rows);
    MPI_Allgather(&first_mode, 1, MPI_UNSIGNED, firsts.data(), 1, MPI_UNSIGNED, d.layout()->comm);
    own_modes = BlockPartition(d.layout()->comm, firsts);
    AssertThrow(own_modes.begin() == first_mode && own_modes.end() == end_mode,
                ExcMessage(
                  "CoarseProblem::distribute: the ranks' modes do not follow each other."));
    own_mode_column.clear();
    for (unsigned int k = row_start[first_mode]; k < row_start[end_mode]; ++k)
      own_mode_column.push_back(d.relevant_index(column[k]));
    // G by the owned columns, modes increasing within each (as in add_Gt).
    const auto &own = d.layout()->global_index;
    if (distributed_only)
      {
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
        return;
      }
    std::vector<unsigned int> local_of_column(n_cols, numbers::invalid_unsigned_int);
    for (unsigned int i = 0; i < own.size(); ++i)
      local_of_column[own[i]] = i;
    own_column_start.assign(own.size() + 1, 0);
    for (const unsigned int c : column)
      if (local_of_column[c] != numbers::invalid_unsigned_int)
        ++own_column_start[local_of_column[c] + 1];
    for (unsigned int i = 0; i < own.size(); ++i)
      own_column_start[i + 1] += own_column_start[i];
    own_column_mode.resize(own_column_start.back());
    own_column_value.resize(own_column_start.back());
    std::vector<unsigned int> next(own_column_start.begin(), own_column_start.end() - 1);
    for (unsigned int r = 0; r < n_rows; ++r)
      for (unsigned int k = row_start[r]; k < row_start[r + 1]; ++k)
        if (const unsigned int i = local_of_column[column[k]]; i != numbers::invalid_unsigned_int)
          {
            own_column_mode[next[i]]    = r;
            own_column_value[next[i]++] = value[k];
          }
  }

  void
  CoarseProblem::apply_G(const DistributedVector &x, Vector<double> &y) const
  {
    Assert(distribution, ExcMessage("CoarseProblem: distribute() first."));
    if (y.size() != n_rows)
      y.reinit(n_rows, true);
    distribution->import(x, relevant_work);
    const unsigned int first = row_start[own_modes.begin()];
    for (unsigned int r = own_modes.begin(); r < own_modes.end(); ++r)
      {
        double s = 0;
        for (unsigned int k = row_start[r]; k < row_start[r + 1]; ++k)
          s += value[k] * relevant_work[own_mode_column[k - first]];
        y[r] = s;
      }
    own_modes.gather(y.begin());
  }

  void
  CoarseProblem::apply_Gt(const Vector<double> &x, Vector<double> &y) const
  {
    add_Gt(x, false, y);
  }

  void
  CoarseProblem::apply_Gt(const Vector<double> &x, DistributedVector &y) const
  {
    add_Gt(x, false, y);
  }

  void
  CoarseProblem::add_Gt(const Vector<double> &x, const bool add, DistributedVector &y) const
  {
    Assert(distribution, ExcMessage("CoarseProblem: distribute() first."));
    Assert(!add || y.get_layout() == distribution->layout(), ExcInternalError());
    if (y.get_layout() != distribution->layout())
      y.reinit(distribution->layout());
    for (unsigned int i = 0; i < y.locally_owned_size(); ++i)
      {
        double s = add ? y[i] : 0.;
        for (unsigned int k = own_column_start[i]; k < own_column_start[i + 1]; ++k)
          s += own_column_value[k] * x[own_column_mode[k]];
        y[i] = s;
      }
  }

  void
  CoarseProblem::add_Gt(const Vector<double> &x, const bool add, Vector<double> &y) const
  {
    AssertThrow(!distributed_only,
                ExcMessage("CoarseProblem: G is distributed; use distributed dual vectors."));
    Assert(!add || y.size() == n_cols, ExcDimensionMismatch(y.size(), n_cols));
    if (y.size() != n_cols)
      y.reinit(n_cols, true);
    const unsigned int first_column = column_blocks.begin();
    for (unsigned int c = first_column; c < column_blocks.end(); ++c)
      {
        const unsigned int j = c - first_column;
        double             s = add ? y[c] : 0.;
        for (unsigned int k = block_column_start[j]; k < block_column_start[j + 1]; ++k)
          s += block_column_value[k] * x[block_column_mode[k]];
        y[c] = s;
      }
    column_blocks.gather(y.begin());
  }

  template <typename VectorType>
  void
  CoarseProblem::apply_G_orthonormal(const VectorType &x, Vector<double> &y) const
  {
    apply_G(x, y);
    if (n_rows > 0)
      GGt.solve_half(y, false);
  }

  template <typename VectorType>
  void
  CoarseProblem::apply_Gt_orthonormal(const Vector<double> &x, VectorType &y) const
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

  template <typename VectorType>
  void
  CoarseProblem::project(VectorType &x) const
  {
    if (n_rows == 0)
      return;
    apply_G(x, work);
    GGt.solve(work);
    // x_c − Σ_r G_rc w_r as x_c + Σ_r G_rc (−w_r): the same numbers.
    work *= -1.;
    add_Gt(work, true, x);
  }

  Vector<double>
  CoarseProblem::least_norm_solution(const Vector<double> &e) const
  {
    Vector<double> mu(e), lambda(n_cols);
    solve_GGt(mu);
    apply_Gt(mu, lambda);
    return lambda;
  }

  void
  CoarseProblem::least_norm_solution(const Vector<double> &e, DistributedVector &lambda) const
  {
    Vector<double> mu(e);
    solve_GGt(mu);
    apply_Gt(mu, lambda);
  }

  Vector<double>
  CoarseProblem::particular_solution(const Vector<double>                            &e,
                                     const std::function<unsigned int(unsigned int)> &tier) const
  {
    Vector<double> lambda(n_cols);
    particular_solution_into(e, tier, lambda);
    return lambda;
  }

  void
  CoarseProblem::particular_solution(const Vector<double>                            &e,
                                     const std::function<unsigned int(unsigned int)> &tier,
                                     DistributedVector                               &lambda) const
  {
    Assert(distribution, ExcMessage("CoarseProblem: distribute() first."));
    lambda.reinit(distribution->layout());
    particular_solution_into(e, tier, lambda);
  }

  template <typename VectorType>
  void
  CoarseProblem::particular_solution_into(const Vector<double>                            &e,
                                          const std::function<unsigned int(unsigned int)> &tier,
                                          VectorType &lambda) const
  {
    const double e_norm = e.l2_norm();
    if (n_rows == 0 || e_norm == 0)
      return;
    constexpr bool     distributed_vector = std::is_same_v<VectorType, DistributedVector>;
    const unsigned int tiers              = tiers_present(tier);
    // The last tier takes every column: the factorization of GGᵀ that exists already.
    for (unsigned int t = 0; (tiers >> (t + 1)) != 0; ++t)
      {
        if (!(tiers & (1u << t)))
          continue;
        const auto           use_column = [&](const unsigned int c) { return tier(c) <= t; };
        SparsityPattern      sp;
        SparseMatrix<double> M;
        if (distributed_only)
          assemble_GGt_distributed(use_column, sp, M);
        else
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
            if constexpr (distributed_vector)
              {
                for (unsigned int i = 0; i < lambda.locally_owned_size(); ++i)
                  if (use_column(lambda.global_index(i)))
                    for (unsigned int k = own_column_start[i]; k < own_column_start[i + 1]; ++k)
                      lambda[i] += own_column_value[k] * r[own_column_mode[k]];
              }
            else
              for (unsigned int m = 0; m < n_rows; ++m)
                for (unsigned int k = row_start[m]; k < row_start[m + 1]; ++k)
                  if (use_column(column[k]))
                    lambda[column[k]] += value[k] * r[m];
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
    if constexpr (distributed_vector)
      least_norm_solution(e, lambda);
    else
      lambda = least_norm_solution(e);
  }

  template <typename VectorType>
  double
  CoarseProblem::restore_feasibility(VectorType &lambda, const Vector<double> &e) const
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
    VectorType correction;
    correction.reinit(lambda);
    apply_Gt(r, correction);
    lambda += correction;
    return misfit;
  }

  template <typename VectorType>
  Vector<double>
  CoarseProblem::coarse_coefficients(const VectorType &x) const
  {
    Vector<double> alpha;
    apply_G(x, alpha);
    solve_GGt(alpha);
    return alpha;
  }
#define FETICONTACT_INSTANTIATE_COARSE_PROBLEM(V)                                                 \
  template void           CoarseProblem::apply_G_orthonormal(const V &, Vector<double> &) const;  \
  template void           CoarseProblem::apply_Gt_orthonormal(const Vector<double> &, V &) const; \
  template void           CoarseProblem::project(V &) const;                                      \
  template double         CoarseProblem::restore_feasibility(V &, const Vector<double> &) const;  \
  template Vector<double> CoarseProblem::coarse_coefficients(const V &) const;

  FETICONTACT_INSTANTIATE_COARSE_PROBLEM(Vector<double>)
  FETICONTACT_INSTANTIATE_COARSE_PROBLEM(DistributedVector)
#undef FETICONTACT_INSTANTIATE_COARSE_PROBLEM
} // namespace FetiContact
