#include <feticontact/base/mpi_tools.h>
#include <feticontact/feti/dual_problem.h>

#include <chrono>
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
        }

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
        add_B(i, x, h);
      }
    MPITools::sum_in_place(comm, e.begin(), e.size());
    MPITools::sum_in_place(comm, h.begin(), h.size());
    h -= c;
    coarse.initialize(comm, G_entries, mode_offset.back(), m);
  }

  void
  DualProblem::add_B(const unsigned int i, const Vector<double> &u, Vector<double> &y) const
  {
    const auto &b = B[i];
    for (unsigned int k = 0; k < b.row.size(); ++k)
      y[b.row[k]] += b.value[k] * u[b.dof[k]];
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
    y.reinit(size());
    for (unsigned int i = 0; i < owned.size(); ++i)
      {
        set_Bt(i, x, work[i]);
        owned[i]->apply_generalized_inverse(work[i]);
        add_B(i, work[i], y);
      }
    MPITools::sum_in_place(comm, y.begin(), y.size());
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
    Vector<double> r(size());
    for (unsigned int i = 0; i < owned.size(); ++i)
      add_B(i, u[i], r);
    MPITools::sum_in_place(comm, r.begin(), r.size());
    r -= c;
    return r;
  }
} // namespace FetiContact
