#include <deal.II/base/mpi.h>

#include <feticontact/base/subdomain_threads.h>
#include <feticontact/feti/dual_problem.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <numeric>
#include <unordered_map>

namespace FetiContact
{
  using namespace dealii;

  DualProblem::DualProblem(const MPI_Comm                     comm,
                           const std::vector<Subdomain *>    &owned,
                           const std::vector<unsigned int>   &mode_offset,
                           const DualRows                    &rows,
                           const CoarseProblem::FactorStorage coarse_factor)
    : coarse(coarse_factor)
    , comm(comm)
    , owned(owned)
    , n_all_rows(rows.n_all)
    , B(owned.size())
    , work(owned.size())
  {
    AssertThrow(std::is_sorted(rows.number.begin(), rows.number.end()),
                ExcMessage("DualProblem: the rows must be in increasing order of their numbers."));

    build_blocks(rows);
    // Every row sums its terms by increasing subdomain, within a subdomain in the order of the
    // entries: on one rank the order of the loop over the subdomains.
    slot_start.assign(rows.row_start.begin(), rows.row_start.end());
    slot_order.resize(rows.entries.size());
    for (unsigned int r = 0; r < rows.n_rows(); ++r)
      {
        const auto first = slot_order.begin() + slot_start[r];
        const auto last  = slot_order.begin() + slot_start[r + 1];
        std::iota(first, last, slot_start[r]);
        std::stable_sort(first, last, [&](const unsigned int a, const unsigned int b) {
          return rows.entries[a].subdomain < rows.entries[b].subdomain;
        });
      }
    const Owners owners = setup_row_sums(rows, mode_offset.size() - 1);
    threaded            = std::all_of(owned.begin(), owned.end(), [](Subdomain *s) {
      return s->local_solver()->thread_safe();
    });

    // G = RᵀBᵀ, e = Rᵀf, h = BK⁺f − c.
    first_mode = mode_offset;
    std::vector<CoarseProblem::Entry> G_entries;
    e.reinit(mode_offset.back());
    for (unsigned int i = 0; i < owned.size(); ++i)
      {
        const Subdomain   &s     = *owned[i];
        const unsigned int first = mode_offset[s.global_index];
        for (unsigned int j = 0; j < s.R.n(); ++j)
          {
            double e_j = 0;
            for (unsigned int d = 0; d < s.R.m(); ++d)
              e_j += s.R(d, j) * s.f[d];
            e[first + j] = e_j;
            // Entries of R at the rounding level of its column are left out of G. The rigid
            // modes are translations and rotations about the centroid, orthonormalized; on a
            // subdomain symmetric about its centroid (the blocks of a structured mesh) the
            // rotations come out orthogonal already, and a DoF of component c then carries
            // one translation and two rotations: the other three entries are zero, or rounding
            // residues of the Gram–Schmidt passes (about 1e-17). Dropping them about halves
            // nnz(G), and with it the cost of the products with G and Gᵀ in every Hessian
            // multiplication; an entry b R(d, j) of G changes by at most 1e-13 |b| max_d |R(d, j)|,
            // far below every tolerance of the solvers (1e-12 at the tightest).
            double R_max = 0;
            for (unsigned int d = 0; d < s.R.m(); ++d)
              R_max = std::max(R_max, std::abs(s.R(d, j)));
            for (unsigned int k = 0; k < B[i].row.size(); ++k)
              if (std::abs(s.R(B[i].dof[k], j)) > 1e-13 * R_max)
                G_entries.push_back({first + j, B[i].row[k], B[i].value[k] * s.R(B[i].dof[k], j)});
          }
      }
    // h: the slots of B K⁺ f, subdomain by subdomain.
    SubdomainThreads::for_each(
      owned.size(),
      [&](const unsigned int i) {
        Vector<double> x(owned[i]->f);
        owned[i]->apply_generalized_inverse(x);
        set_B_slots(i, x);
      },
      threaded);
    Utilities::MPI::sum(ArrayView<const double>(e.begin(), e.size()),
                        comm,
                        ArrayView<double>(e.begin(), e.size()));
    set_up_right_hand_sides(rows);
    const auto [first_own_mode, end_own_mode] = own_modes(mode_offset);
    coarse.initialize(*dual_space,
                      relevant_G_entries(G_entries, rows, owners),
                      mode_offset.back(),
                      size(),
                      first_own_mode,
                      end_own_mode);
  }

  void
  DualProblem::set_up_right_hand_sides(const DualRows &rows)
  {
    // The slots hold B K⁺ f.
    c = dual_space->vector();
    for (unsigned int j = 0; j < dual_space->n_owned(); ++j)
      c.local_element(j) = rows.c[index_of_row(rows, dual_space->row(j))];
    sum_rows_into(h);
    h -= c;
  }

  std::vector<CoarseProblem::Entry>
  DualProblem::relevant_G_entries(const std::vector<CoarseProblem::Entry> &own_entries,
                                  const DualRows                          &rows,
                                  const Owners                            &owners) const
  {
    // An entry of column c goes to the ranks of the subdomains in row c and to the rank that
    // owns row c: every rank then holds every entry of its relevant columns.
    const int                         this_rank = Utilities::MPI::this_mpi_process(comm);
    std::vector<CoarseProblem::Entry> relevant;
    std::map<unsigned int, std::vector<CoarseProblem::Entry>> send;
    std::vector<int>                                          ranks;
    for (const CoarseProblem::Entry &e : own_entries)
      {
        relevant.push_back(e);
        const unsigned int r = index_of_row(rows, e.column);
        ranks.assign(1, owners.row_rank[r]);
        for (unsigned int k = rows.row_start[r]; k < rows.row_start[r + 1]; ++k)
          ranks.push_back(owners.subdomain_rank[rows.entries[k].subdomain]);
        std::sort(ranks.begin(), ranks.end());
        ranks.erase(std::unique(ranks.begin(), ranks.end()), ranks.end());
        for (const int p : ranks)
          if (p != this_rank)
            send[p].push_back(e);
      }
    for (const auto &[rank, entries] : Utilities::MPI::some_to_some(comm, send))
      relevant.insert(relevant.end(), entries.begin(), entries.end());
    return relevant;
  }

  void
  DualProblem::build_blocks(const DualRows &rows)
  {
    // B_i: the entries of the rows that touch subdomain i, with DoFs looked up by body vertex.
    std::unordered_map<unsigned int, unsigned int> local_of_global;
    for (unsigned int i = 0; i < owned.size(); ++i)
      local_of_global[owned[i]->global_index] = i;
    std::vector<std::unordered_map<unsigned int, unsigned int>> vertex_of_body_vertex(owned.size());
    for (unsigned int i = 0; i < owned.size(); ++i)
      {
        for (unsigned int v = 0; v < owned[i]->body_vertex.size(); ++v)
          vertex_of_body_vertex[i][owned[i]->body_vertex[v]] = v;
        work[i].reinit(owned[i]->dof_handler.n_dofs());
      }
    for (unsigned int r = 0; r < rows.n_rows(); ++r)
      for (unsigned int k = rows.row_start[r]; k < rows.row_start[r + 1]; ++k)
        {
          const auto &entry = rows.entries[k];
          const auto  it    = local_of_global.find(entry.subdomain);
          if (it == local_of_global.end())
            continue;
          const unsigned int i = it->second;
          const unsigned int v = vertex_of_body_vertex[i].at(entry.body_vertex);
          B[i].row.push_back(rows.number[r]);
          B[i].dof.push_back(owned[i]->vertex_dofs[v][entry.component]);
          B[i].value.push_back(entry.value);
          B[i].slot.push_back(k);
        }
  }

  std::pair<unsigned int, unsigned int>
  DualProblem::own_modes(const std::vector<unsigned int> &mode_offset) const
  {
    // G x on distributed vectors: every rank the modes of its subdomains, which follow each other
    // in rank order (contiguous ranges of subdomains, SubdomainDistribution::owners()).
    unsigned int n_own_modes = 0, first_own_mode = 0;
    for (const Subdomain *s : owned)
      n_own_modes += mode_offset[s->global_index + 1] - mode_offset[s->global_index];
    MPI_Exscan(&n_own_modes, &first_own_mode, 1, MPI_UNSIGNED, MPI_SUM, comm);
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      first_own_mode = 0;
    for (unsigned int i = 0; i < owned.size(); ++i)
      AssertThrow(mode_offset[owned[i]->global_index] ==
                    (i == 0 ? first_own_mode : mode_offset[owned[i - 1]->global_index + 1]),
                  ExcMessage("DualProblem: the subdomains of the ranks must be contiguous ranges "
                             "in rank order."));
    return {first_own_mode, first_own_mode + n_own_modes};
  }

  void
  DualProblem::set_B_slots(const unsigned int i, const Vector<double> &u) const
  {
    const auto &b = B[i];
    for (unsigned int k = 0; k < b.row.size(); ++k)
      slots.local_element(b.slot[k]) = b.value[k] * u[b.dof[k]];
  }

  unsigned int
  DualProblem::index_of_row(const DualRows &rows, const unsigned int number)
  {
    const auto it = std::lower_bound(rows.number.begin(), rows.number.end(), number);
    AssertThrow(it != rows.number.end() && *it == number,
                ExcMessage("DualProblem: row " + std::to_string(number) + " is not here."));
    return it - rows.number.begin();
  }

  DualProblem::Owners
  DualProblem::setup_row_sums(const DualRows &rows, const unsigned int n_subdomains)
  {
    Owners owners = row_owners(rows, n_subdomains);
    set_up_space(rows, owners);
    set_up_slots(rows, owners);
    return owners;
  }

  int
  DualProblem::Owners::rank_of_entry(const DualRows &rows, const unsigned int k) const
  {
    const unsigned int s = rows.entries[k].subdomain;
    AssertThrow(s < subdomain_rank.size() && subdomain_rank[s] >= 0,
                ExcMessage("DualProblem: a row of B refers to subdomain " + std::to_string(s) +
                           ", which no rank owns."));
    return subdomain_rank[s];
  }

  DualProblem::Owners
  DualProblem::row_owners(const DualRows &rows, const unsigned int n_subdomains) const
  {
    const int          n_ranks   = Utilities::MPI::n_mpi_processes(comm);
    const int          this_rank = Utilities::MPI::this_mpi_process(comm);
    const unsigned int n         = rows.n_rows();

    // The rank of every subdomain, and of every row: the rank of the first subdomain in the
    // row's summation order (rank 0 for a row without coefficients).
    Owners owners;
    owners.subdomain_rank.assign(n_subdomains, -1);
    for (const Subdomain *s : owned)
      owners.subdomain_rank[s->global_index] = this_rank;
    if (n_subdomains > 0)
      MPI_Allreduce(
        MPI_IN_PLACE, owners.subdomain_rank.data(), n_subdomains, MPI_INT, MPI_MAX, comm);
    // The first subdomain of every row (of a set of rows held together: the lowest of its rows,
    // or the subdomain the set names, DualRows::held_by), its rank and its chunk of the dual
    // vectors' sums: a chunk is the same rows on any number of ranks,
    // and all on one rank (the subdomains of a rank are a contiguous range). Which rank adds up
    // a row does not change its sum. Every rank that holds a row holds its whole set, and so
    // gives it the same rank.
    owners.first_subdomain.assign(n, 0);
    owners.row_rank.assign(n, 0);
    for (unsigned int r = 0; r < n; ++r)
      if (slot_start[r] < slot_start[r + 1])
        {
          owners.first_subdomain[r] = rows.entries[slot_order[slot_start[r]]].subdomain;
          owners.row_rank[r]        = owners.rank_of_entry(rows, slot_order[slot_start[r]]);
        }
    AssertThrow(rows.held_by.size() == rows.held_together.size(),
                ExcMessage("DualProblem: DualRows::held_by must name one subdomain (or none) per "
                           "set of rows held together."));
    for (unsigned int i = 0; i < rows.held_together.size(); ++i)
      {
        const auto  &set   = rows.held_together[i];
        unsigned int first = numbers::invalid_unsigned_int;
        int          rank  = n_ranks;
        if (rows.held_by[i] != numbers::invalid_unsigned_int)
          {
            first = rows.held_by[i];
            rank  = owners.subdomain_rank.at(first);
            AssertThrow(rank >= 0,
                        ExcMessage("DualProblem: rows are held by subdomain " +
                                   std::to_string(first) + ", which no rank owns."));
          }
        else
          for (const unsigned int r : set)
            {
              first = std::min(first, owners.first_subdomain[r]);
              rank  = std::min(rank, owners.row_rank[r]);
            }
        for (const unsigned int r : set)
          {
            owners.first_subdomain[r] = first;
            owners.row_rank[r]        = rank;
          }
      }
    return owners;
  }

  void
  DualProblem::set_up_space(const DualRows &rows, const Owners &owners)
  {
    // The dual vectors: this rank's rows, and as ghosts the other rows of its subdomains.
    const int                 this_rank = Utilities::MPI::this_mpi_process(comm);
    std::vector<unsigned int> owned_rows, chunk, ghost_rows;
    for (unsigned int r = 0; r < rows.n_rows(); ++r)
      if (owners.row_rank[r] == this_rank)
        {
          owned_rows.push_back(rows.number[r]);
          chunk.push_back(owners.first_subdomain[r]);
        }
    for (const auto &b : B)
      ghost_rows.insert(ghost_rows.end(), b.row.begin(), b.row.end());
    std::sort(ghost_rows.begin(), ghost_rows.end());
    ghost_rows.erase(std::unique(ghost_rows.begin(), ghost_rows.end()), ghost_rows.end());
    std::vector<int>          ghost_owner;
    std::vector<unsigned int> ghosts;
    for (const unsigned int row : ghost_rows)
      {
        const int owner = owners.row_rank[index_of_row(rows, row)];
        if (owner != this_rank)
          {
            ghosts.push_back(row);
            ghost_owner.push_back(owner);
          }
      }
    dual_space = std::make_unique<DualSpace>(comm, owned_rows, chunk, ghosts, ghost_owner, size());
    row_local.resize(B.size());
    for (unsigned int i = 0; i < B.size(); ++i)
      {
        row_local[i].resize(B[i].row.size());
        for (unsigned int k = 0; k < B[i].row.size(); ++k)
          row_local[i][k] = dual_space->local_index(B[i].row[k]);
      }
  }

  void
  DualProblem::set_up_slots(const DualRows &rows, const Owners &owners)
  {
    // The slots numbered by the rows' order in the dual vectors, a row's slots in its summation
    // order: every rank owns the slots of its rows, and those its subdomains write in other
    // ranks' rows are its ghosts.
    const int                 this_rank = Utilities::MPI::this_mpi_process(comm);
    const unsigned int        n_owned   = dual_space->n_owned();
    std::vector<unsigned int> position(rows.entries.size()); // of an entry in its row's order
    for (unsigned int r = 0; r < rows.n_rows(); ++r)
      for (unsigned int p = slot_start[r]; p < slot_start[r + 1]; ++p)
        position[slot_order[p]] = p - slot_start[r];
    row_slot_start.assign(1, 0);
    foreign_slots.clear();
    for (unsigned int j = 0; j < n_owned; ++j)
      {
        const unsigned int r = index_of_row(rows, dual_space->row(j));
        for (unsigned int p = slot_start[r]; p < slot_start[r + 1]; ++p)
          if (owners.rank_of_entry(rows, slot_order[p]) != this_rank)
            foreign_slots.push_back(row_slot_start.back() + p - slot_start[r]);
        row_slot_start.push_back(row_slot_start.back() + slot_start[r + 1] - slot_start[r]);
      }
    unsigned long long n_own_slots = row_slot_start.back(), first = 0, n_slots = 0;
    MPI_Exscan(&n_own_slots, &first, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
    if (this_rank == 0)
      first = 0;
    MPI_Allreduce(&n_own_slots, &n_slots, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);

    // The first slot of every row of this rank's subdomains, from the row's owner.
    DualVector first_slot = dual_space->vector();
    for (unsigned int j = 0; j < n_owned; ++j)
      first_slot.local_element(j) = first + row_slot_start[j];
    first_slot.update_ghost_values();
    std::vector<types::global_dof_index> slot_index;
    IndexSet                             owned_slots(n_slots), ghost_slots(n_slots);
    owned_slots.add_range(first, first + n_own_slots);
    for (unsigned int i = 0; i < B.size(); ++i)
      for (unsigned int k = 0; k < B[i].row.size(); ++k)
        {
          const auto index = types::global_dof_index(first_slot.local_element(row_local[i][k])) +
                             position[B[i].slot[k]];
          slot_index.push_back(index);
          if (!owned_slots.is_element(index))
            ghost_slots.add_index(index);
        }
    ghost_slots.compress();
    slots.reinit(
      std::make_shared<const Utilities::MPI::Partitioner>(owned_slots, ghost_slots, comm));
    std::size_t n = 0;
    for (auto &b : B)
      for (unsigned int &slot : b.slot)
        slot = slots.get_partitioner()->global_to_local(slot_index[n++]);
  }

  DualProblem::CommunicationVolume
  DualProblem::communication_volume() const
  {
    CommunicationVolume v;
    const auto         &slot_partitioner = *slots.get_partitioner();
    std::vector<int>    slot_ranks;
    for (const auto &[rank, n] : slot_partitioner.ghost_targets())
      {
        v.slots_sent += n;
        slot_ranks.push_back(rank);
      }
    for (const auto &[rank, n] : slot_partitioner.import_targets())
      {
        v.slots_received += n;
        slot_ranks.push_back(rank);
      }
    std::sort(slot_ranks.begin(), slot_ranks.end());
    v.slot_neighbours  = std::unique(slot_ranks.begin(), slot_ranks.end()) - slot_ranks.begin();
    v.ghost_neighbours = dual_space->partitioner()->ghost_targets().size();
    v.ghosts_received  = dual_space->partitioner()->n_ghost_indices();
    return v;
  }

  void
  DualProblem::exchange_slots() const
  {
    // The terms of other ranks' subdomains in this rank's rows are added to zero (exact), and
    // this rank's terms in other ranks' rows sent to them (only rows on the boundaries between
    // the ranks' sets of subdomains).
    for (const unsigned int j : foreign_slots)
      slots.local_element(j) = 0;
    slots.compress(VectorOperation::add);
  }

  void
  DualProblem::sum_own_rows(double *sums) const
  {
    for (unsigned int j = 0; j + 1 < row_slot_start.size(); ++j)
      {
        double sum = 0;
        for (unsigned int k = row_slot_start[j]; k < row_slot_start[j + 1]; ++k)
          sum += slots.local_element(k);
        sums[j] = sum;
      }
  }

  void
  DualProblem::set_Bt(const unsigned int i, const DualVector &lambda, Vector<double> &x) const
  {
    x             = 0;
    const auto &b = B[i];
    const auto &r = row_local[i];
    for (unsigned int k = 0; k < b.row.size(); ++k)
      x[b.dof[k]] += b.value[k] * lambda.local_element(r[k]);
  }

  void
  DualProblem::apply_F(const DualVector &x, DualVector &y) const
  {
    const auto start = std::chrono::steady_clock::now();
    x.update_ghost_values();
    SubdomainThreads::for_each(
      owned.size(),
      [&](const unsigned int i) {
        set_Bt(i, x, work[i]);
        owned[i]->apply_generalized_inverse(work[i]);
        set_B_slots(i, work[i]);
      },
      threaded);
    x.zero_out_ghost_values();
    n_subdomain_solves += owned.size();
    F_local_time += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    sum_rows_into(y);
    ++n_F_applications;
    F_time += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  void
  DualProblem::sum_rows_into(DualVector &y) const
  {
    exchange_slots();
    if (y.get_partitioner() != dual_space->partitioner())
      y.reinit(dual_space->partitioner());
    sum_own_rows(y.begin());
  }

  void
  DualProblem::apply_lumped(const DualVector &x, DualVector &y) const
  {
    const auto start = std::chrono::steady_clock::now();
    if (lumped_scale.size() == 0)
      {
        // diag(B Bᵀ)⁻¹ on this rank's rows, then on its ghosts.
        for (unsigned int i = 0; i < owned.size(); ++i)
          {
            const auto &b = B[i];
            for (unsigned int k = 0; k < b.row.size(); ++k)
              slots.local_element(b.slot[k]) = b.value[k] * b.value[k];
          }
        sum_rows_into(lumped_scale);
        for (auto &di : lumped_scale)
          di = di > 0 ? 1 / di : 0.;
        lumped_scale.update_ghost_values();
      }
    if (x_scaled.get_partitioner() != dual_space->partitioner())
      x_scaled.reinit(dual_space->partitioner());
    for (unsigned int j = 0; j < dual_space->n_owned(); ++j)
      x_scaled.local_element(j) = x.local_element(j) * lumped_scale.local_element(j);
    x_scaled.update_ghost_values();
    lumped_Ku.resize(owned.size());
    SubdomainThreads::for_each(owned.size(), [&](const unsigned int i) {
      set_Bt(i, x_scaled, work[i]);
      lumped_Ku[i].reinit(work[i].size(), true);
      owned[i]->K.vmult(lumped_Ku[i], work[i]);
      set_B_slots(i, lumped_Ku[i]);
    });
    x_scaled.zero_out_ghost_values();
    sum_rows_into(y);
    for (unsigned int j = 0; j < dual_space->n_owned(); ++j)
      y.local_element(j) *= lumped_scale.local_element(j);
    ++n_lumped_applications;
    lumped_time += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  std::vector<Vector<double>>
  DualProblem::recover_primal(const DualVector &lambda) const
  {
    DualVector gradient;
    apply_F(lambda, gradient);
    gradient -= h;
    return recover_primal(lambda, coarse.coarse_coefficients(gradient));
  }

  std::vector<Vector<double>>
  DualProblem::recover_primal(const DualVector &lambda, const Vector<double> &alpha) const
  {
    std::vector<Vector<double>> u(owned.size());
    lambda.update_ghost_values();
    SubdomainThreads::for_each(
      owned.size(),
      [&](const unsigned int i) {
        const Subdomain &s = *owned[i];
        set_Bt(i, lambda, work[i]);
        u[i] = s.f;
        u[i] -= work[i];
        s.apply_generalized_inverse(u[i]);
        for (unsigned int j = 0; j < s.R.n(); ++j)
          for (unsigned int d = 0; d < s.R.m(); ++d)
            u[i][d] += s.R(d, j) * alpha[first_mode[s.global_index] + j];
      },
      threaded);
    lambda.zero_out_ghost_values();
    return u;
  }

  DualVector
  DualProblem::constraint_residual(const std::vector<Vector<double>> &u) const
  {
    for (unsigned int i = 0; i < owned.size(); ++i)
      set_B_slots(i, u[i]);
    DualVector r;
    sum_rows_into(r);
    r -= c;
    return r;
  }
} // namespace FetiContact
