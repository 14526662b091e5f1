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
    slots.assign(rows.entries.size(), 0.);
    threaded = std::all_of(owned.begin(), owned.end(), [](Subdomain *s) {
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
    coarse.initialize(*row_distribution,
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
    c = row_distribution->vector();
    for (unsigned int j = 0; j < own_local.size(); ++j)
      c[j] = rows.c[own_local[j]];
    h = row_distribution->vector();
    exchange_slots();
    sum_own_rows(h.begin());
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
    // in rank order (contiguous ranges of subdomains, Simulator::distribute_subdomains).
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
      slots[b.slot[k]] = b.value[k] * u[b.dof[k]];
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
    set_up_slot_exchanges(rows, owners);
    set_up_own_rows(rows, owners);
    set_up_distribution(rows, owners);
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
  DualProblem::set_up_slot_exchanges(const DualRows &rows, const Owners &owners)
  {
    // The slots that cross ranks: terms of this rank's subdomains in other ranks' rows (sent)
    // and the other way round (received), both listed by increasing row number and, within a
    // row, in the order of its entries, on either side.
    const int                                this_rank = Utilities::MPI::this_mpi_process(comm);
    std::map<int, std::vector<unsigned int>> send, receive;
    for (unsigned int r = 0; r < rows.n_rows(); ++r)
      for (unsigned int k = slot_start[r]; k < slot_start[r + 1]; ++k)
        {
          const int from = owners.rank_of_entry(rows, k), to = owners.row_rank[r];
          if (from == to)
            continue;
          if (from == this_rank)
            send[to].push_back(k);
          else if (to == this_rank)
            receive[from].push_back(k);
        }
    send_slots.clear();
    receive_slots.clear();
    for (auto &[p, list] : send)
      send_slots.push_back({p, std::move(list), {}});
    for (auto &[p, list] : receive)
      receive_slots.push_back({p, std::move(list), {}});
    for (auto &exchange : send_slots)
      exchange.buffer.resize(exchange.slots.size());
    for (auto &exchange : receive_slots)
      exchange.buffer.resize(exchange.slots.size());
    requests.resize(send_slots.size() + receive_slots.size());
  }

  void
  DualProblem::set_up_own_rows(const DualRows &rows, const Owners &owners)
  {
    const int          n_ranks   = Utilities::MPI::n_mpi_processes(comm);
    const int          this_rank = Utilities::MPI::this_mpi_process(comm);
    const unsigned int n         = rows.n_rows();
    own_rows.clear();
    own_local.clear();
    for (unsigned int r = 0; r < n; ++r)
      if (owners.row_rank[r] == this_rank)
        {
          own_rows.push_back(rows.number[r]);
          own_local.push_back(r);
        }
  }

  void
  DualProblem::set_up_distribution(const DualRows &rows, const Owners &owners)
  {
    // The distributed dual vectors: this rank's rows, and the rows of its subdomains.
    std::vector<unsigned int> relevant(own_rows);
    for (const auto &b : B)
      relevant.insert(relevant.end(), b.row.begin(), b.row.end());
    std::sort(relevant.begin(), relevant.end());
    relevant.erase(std::unique(relevant.begin(), relevant.end()), relevant.end());
    std::vector<int> relevant_owner(relevant.size());
    for (unsigned int j = 0; j < relevant.size(); ++j)
      relevant_owner[j] = owners.row_rank[index_of_row(rows, relevant[j])];
    std::vector<unsigned int> chunk_of_own_row(own_rows.size());
    for (unsigned int j = 0; j < own_rows.size(); ++j)
      chunk_of_own_row[j] = owners.first_subdomain[own_local[j]];
    row_distribution = std::make_unique<DualDistribution>(
      comm, own_rows, relevant, relevant_owner, size(), chunk_of_own_row);
    relevant_row.resize(B.size());
    for (unsigned int i = 0; i < B.size(); ++i)
      {
        relevant_row[i].resize(B[i].row.size());
        for (unsigned int k = 0; k < B[i].row.size(); ++k)
          relevant_row[i][k] = row_distribution->relevant_index(B[i].row[k]);
      }
  }

  DualProblem::CommunicationVolume
  DualProblem::communication_volume() const
  {
    CommunicationVolume v;
    std::vector<int>    slot_ranks;
    for (const auto &exchange : send_slots)
      {
        v.slots_sent += exchange.slots.size();
        slot_ranks.push_back(exchange.rank);
      }
    for (const auto &exchange : receive_slots)
      {
        v.slots_received += exchange.slots.size();
        slot_ranks.push_back(exchange.rank);
      }
    std::sort(slot_ranks.begin(), slot_ranks.end());
    v.slot_neighbours  = std::unique(slot_ranks.begin(), slot_ranks.end()) - slot_ranks.begin();
    v.ghost_neighbours = row_distribution->n_neighbours();
    v.ghosts_received  = row_distribution->n_received();
    return v;
  }

  void
  DualProblem::exchange_slots() const
  {
    // The terms that other ranks' rows need from this rank, and those this rank's rows need
    // from others (only rows on the boundaries between the ranks' sets of subdomains).
    unsigned int n_requests = 0;
    for (auto &exchange : receive_slots)
      MPI_Irecv(exchange.buffer.data(),
                exchange.buffer.size(),
                MPI_DOUBLE,
                exchange.rank,
                0,
                comm,
                &requests[n_requests++]);
    for (auto &exchange : send_slots)
      {
        for (unsigned int j = 0; j < exchange.slots.size(); ++j)
          exchange.buffer[j] = slots[exchange.slots[j]];
        MPI_Isend(exchange.buffer.data(),
                  exchange.buffer.size(),
                  MPI_DOUBLE,
                  exchange.rank,
                  0,
                  comm,
                  &requests[n_requests++]);
      }
    MPI_Waitall(n_requests, requests.data(), MPI_STATUSES_IGNORE);
    for (const auto &exchange : receive_slots)
      for (unsigned int j = 0; j < exchange.slots.size(); ++j)
        slots[exchange.slots[j]] = exchange.buffer[j];
  }

  void
  DualProblem::sum_own_rows(double *sums) const
  {
    for (unsigned int j = 0; j < own_local.size(); ++j)
      {
        const unsigned int r   = own_local[j];
        double             sum = 0;
        for (unsigned int k = slot_start[r]; k < slot_start[r + 1]; ++k)
          sum += slots[slot_order[k]];
        sums[j] = sum;
      }
  }

  void
  DualProblem::set_Bt_relevant(const unsigned int    i,
                               const Vector<double> &lambda_relevant,
                               Vector<double>       &x) const
  {
    x             = 0;
    const auto &b = B[i];
    const auto &r = relevant_row[i];
    for (unsigned int k = 0; k < b.row.size(); ++k)
      x[b.dof[k]] += b.value[k] * lambda_relevant[r[k]];
  }

  void
  DualProblem::apply_F(const DistributedVector &x, DistributedVector &y) const
  {
    const auto start = std::chrono::steady_clock::now();
    row_distribution->import(x, x_relevant);
    apply_F_relevant(x_relevant, y);
    F_time += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  void
  DualProblem::apply_F_relevant(const Vector<double> &x, DistributedVector &y) const
  {
    const auto start = std::chrono::steady_clock::now();
    SubdomainThreads::for_each(
      owned.size(),
      [&](const unsigned int i) {
        set_Bt_relevant(i, x, work[i]);
        owned[i]->apply_generalized_inverse(work[i]);
        set_B_slots(i, work[i]);
      },
      threaded);
    n_subdomain_solves += owned.size();
    F_local_time += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    exchange_slots();
    if (y.get_layout() != row_distribution->layout())
      y.reinit(row_distribution->layout());
    sum_own_rows(y.begin());
    ++n_F_applications;
  }

  void
  DualProblem::apply_lumped(const DistributedVector &x, DistributedVector &y) const
  {
    const auto start = std::chrono::steady_clock::now();
    if (lumped_scale_relevant.size() != row_distribution->relevant_rows().size())
      {
        // diag(B Bᵀ)⁻¹ on this rank's rows, then on the relevant rows.
        for (unsigned int i = 0; i < owned.size(); ++i)
          {
            const auto &b = B[i];
            for (unsigned int k = 0; k < b.row.size(); ++k)
              slots[b.slot[k]] = b.value[k] * b.value[k];
          }
        exchange_slots();
        DistributedVector d = row_distribution->vector();
        sum_own_rows(d.begin());
        for (auto &di : d)
          di = di > 0 ? 1 / di : 0.;
        row_distribution->import(d, lumped_scale_relevant);
      }
    row_distribution->import(x, x_relevant);
    x_relevant.scale(lumped_scale_relevant);
    lumped_Ku.resize(owned.size());
    SubdomainThreads::for_each(owned.size(), [&](const unsigned int i) {
      set_Bt_relevant(i, x_relevant, work[i]);
      lumped_Ku[i].reinit(work[i].size(), true);
      owned[i]->K.vmult(lumped_Ku[i], work[i]);
      set_B_slots(i, lumped_Ku[i]);
    });
    exchange_slots();
    if (y.get_layout() != row_distribution->layout())
      y.reinit(row_distribution->layout());
    sum_own_rows(y.begin());
    const auto &own = row_distribution->owned_relevant_indices();
    for (unsigned int j = 0; j < own.size(); ++j)
      y[j] *= lumped_scale_relevant[own[j]];
    ++n_lumped_applications;
    lumped_time += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  std::vector<Vector<double>>
  DualProblem::recover_primal(const DistributedVector &lambda) const
  {
    DistributedVector gradient;
    apply_F(lambda, gradient);
    gradient -= h;
    return recover_primal(lambda, coarse.coarse_coefficients(gradient));
  }

  std::vector<Vector<double>>
  DualProblem::recover_primal(const DistributedVector &lambda, const Vector<double> &alpha) const
  {
    row_distribution->import(lambda, x_relevant);
    return recover_primal_relevant(x_relevant, alpha);
  }

  std::vector<Vector<double>>
  DualProblem::recover_primal_relevant(const Vector<double> &lambda_relevant,
                                       const Vector<double> &alpha) const
  {
    std::vector<Vector<double>> u(owned.size());
    SubdomainThreads::for_each(
      owned.size(),
      [&](const unsigned int i) {
        const Subdomain &s = *owned[i];
        set_Bt_relevant(i, lambda_relevant, work[i]);
        u[i] = s.f;
        u[i] -= work[i];
        s.apply_generalized_inverse(u[i]);
        for (unsigned int j = 0; j < s.R.n(); ++j)
          for (unsigned int d = 0; d < s.R.m(); ++d)
            u[i][d] += s.R(d, j) * alpha[first_mode[s.global_index] + j];
      },
      threaded);
    return u;
  }

  DistributedVector
  DualProblem::constraint_residual(const std::vector<Vector<double>> &u) const
  {
    for (unsigned int i = 0; i < owned.size(); ++i)
      set_B_slots(i, u[i]);
    DistributedVector r = row_distribution->vector();
    exchange_slots();
    sum_own_rows(r.begin());
    r -= c;
    return r;
  }
} // namespace FetiContact
