#include <feticontact/base/mpi_tools.h>
#include <feticontact/feti/dual_problem.h>

#include <algorithm>
#include <chrono>
#include <numeric>
#include <unordered_map>

namespace FetiContact
{
  using namespace dealii;

  DualProblem::DualProblem(const MPI_Comm                   comm,
                           const std::vector<Subdomain *>  &owned,
                           const std::vector<unsigned int> &mode_offset,
                           const DualRows                  &rows)
    : comm(comm)
    , owned(owned)
    , B(owned.size())
    , work(owned.size())
  {
    const unsigned int m = rows.n_rows();
    c.reinit(m);
    for (unsigned int r = 0; r < m; ++r)
      c[r] = rows.c[r];

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
    for (unsigned int r = 0; r < m; ++r)
      for (unsigned int k = rows.row_start[r]; k < rows.row_start[r + 1]; ++k)
        {
          const auto &entry = rows.entries[k];
          const auto  it    = local_of_global.find(entry.subdomain);
          if (it == local_of_global.end())
            continue;
          const unsigned int i = it->second;
          const unsigned int v = vertex_of_body_vertex[i].at(entry.body_vertex);
          B[i].row.push_back(r);
          B[i].dof.push_back(owned[i]->vertex_dofs[v][entry.component]);
          B[i].value.push_back(entry.value);
          B[i].slot.push_back(k);
        }
    // Every row sums its terms by increasing subdomain, within a subdomain in the order of the
    // entries: on one rank the order of the loop over the subdomains.
    slot_start.assign(rows.row_start.begin(), rows.row_start.end());
    slot_order.resize(rows.entries.size());
    for (unsigned int r = 0; r < m; ++r)
      {
        const auto first = slot_order.begin() + slot_start[r];
        const auto last  = slot_order.begin() + slot_start[r + 1];
        std::iota(first, last, slot_start[r]);
        std::stable_sort(first, last, [&](const unsigned int a, const unsigned int b) {
          return rows.entries[a].subdomain < rows.entries[b].subdomain;
        });
      }
    slots.assign(rows.entries.size(), 0.);
    summed_slots.assign(rows.entries.size(), 0.);
    // The rows are split among the ranks in blocks of about equal numbers of slots; the slots of
    // a block of rows are a block too (they are numbered row by row).
    row_blocks = BlockPartition::balanced(comm, slot_start);
    std::vector<unsigned int> first_slot;
    for (const unsigned int r : row_blocks.firsts())
      first_slot.push_back(slot_start[r]);
    slot_blocks = BlockPartition(comm, first_slot);

    // G = RᵀBᵀ, e = Rᵀf, h = BK⁺f − c.
    first_mode = mode_offset;
    std::vector<CoarseProblem::Entry> G_entries;
    e.reinit(mode_offset.back());
    h.reinit(m);
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
            for (unsigned int k = 0; k < B[i].row.size(); ++k)
              G_entries.push_back({first + j, B[i].row[k], B[i].value[k] * s.R(B[i].dof[k], j)});
          }
        Vector<double> x(s.f);
        s.apply_generalized_inverse(x);
        set_B_slots(i, x);
      }
    MPITools::sum_in_place(comm, e.begin(), e.size());
    sum_slots(h);
    h -= c;
    coarse.initialize(comm, G_entries, mode_offset.back(), m);
  }

  void
  DualProblem::set_B_slots(const unsigned int i, const Vector<double> &u) const
  {
    const auto &b = B[i];
    for (unsigned int k = 0; k < b.row.size(); ++k)
      slots[b.slot[k]] = b.value[k] * u[b.dof[k]];
  }

  void
  DualProblem::sum_slots(Vector<double> &y) const
  {
    // Every rank sums the slots of its block of rows over the ranks and adds them up row by row;
    // the rows are then gathered.
    slot_blocks.sum_scatter(slots.data(), summed_slots.data() + slot_blocks.begin());
    if (y.size() != size())
      y.reinit(size(), true);
    for (unsigned int r = row_blocks.begin(); r < row_blocks.end(); ++r)
      {
        double sum = 0;
        for (unsigned int k = slot_start[r]; k < slot_start[r + 1]; ++k)
          sum += summed_slots[slot_order[k]];
        y[r] = sum;
      }
    row_blocks.gather(y.begin());
  }

  void
  DualProblem::set_Bt(const unsigned int i, const Vector<double> &lambda, Vector<double> &x) const
  {
    x             = 0;
    const auto &b = B[i];
    for (unsigned int k = 0; k < b.row.size(); ++k)
      x[b.dof[k]] += b.value[k] * lambda[b.row[k]];
  }

  void
  DualProblem::apply_F(const Vector<double> &x, Vector<double> &y) const
  {
    const auto start = std::chrono::steady_clock::now();
    for (unsigned int i = 0; i < owned.size(); ++i)
      {
        set_Bt(i, x, work[i]);
        owned[i]->apply_generalized_inverse(work[i]);
        set_B_slots(i, work[i]);
      }
    F_local_time += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    sum_slots(y);
    ++n_F_applications;
    F_time += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  std::vector<Vector<double>>
  DualProblem::recover_primal(const Vector<double> &lambda) const
  {
    Vector<double> gradient;
    apply_F(lambda, gradient);
    gradient -= h;
    return recover_primal(lambda, coarse.coarse_coefficients(gradient));
  }

  std::vector<Vector<double>>
  DualProblem::recover_primal(const Vector<double> &lambda, const Vector<double> &alpha) const
  {
    std::vector<Vector<double>> u(owned.size());
    for (unsigned int i = 0; i < owned.size(); ++i)
      {
        const Subdomain &s = *owned[i];
        set_Bt(i, lambda, work[i]);
        u[i] = s.f;
        u[i] -= work[i];
        s.apply_generalized_inverse(u[i]);
        for (unsigned int j = 0; j < s.R.n(); ++j)
          for (unsigned int d = 0; d < s.R.m(); ++d)
            u[i][d] += s.R(d, j) * alpha[first_mode[s.global_index] + j];
      }
    return u;
  }

  Vector<double>
  DualProblem::constraint_residual(const std::vector<Vector<double>> &u) const
  {
    Vector<double> r;
    for (unsigned int i = 0; i < owned.size(); ++i)
      set_B_slots(i, u[i]);
    sum_slots(r);
    r -= c;
    return r;
  }
} // namespace FetiContact
