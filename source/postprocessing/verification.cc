#include <deal.II/dofs/dof_handler.h>

#include <feticontact/base/mpi_tools.h>
#include <feticontact/local_solvers/cholmod_solver.h>
#include <feticontact/postprocessing/verification.h>
#include <feticontact/subdomain/elasticity_assembly.h>

namespace FetiContact
{
  using namespace dealii;

  std::vector<std::vector<Tensor<1, 3>>>
  gather_vertex_displacements(const MPI_Comm                            comm,
                              const std::vector<std::unique_ptr<Body>> &bodies,
                              const std::vector<unsigned int>          &first_subdomain,
                              const std::vector<Subdomain *>           &owned,
                              const std::vector<Vector<double>>        &u)
  {
    std::vector<std::vector<Tensor<1, 3>>> result(bodies.size());
    std::vector<std::vector<unsigned int>> lowest(bodies.size());
    for (const auto &body : bodies)
      {
        result[body->index].resize(body->mesh.n_vertices());
        auto &low = lowest[body->index];
        low.assign(body->mesh.n_vertices(), numbers::invalid_unsigned_int);
        const auto parts = parts_of_vertices(body->mesh, body->partition);
        for (unsigned int v = 0; v < parts.size(); ++v)
          if (!parts[v].empty())
            low[v] = first_subdomain[body->index] + parts[v].front();
      }
    for (unsigned int i = 0; i < owned.size(); ++i)
      {
        const Subdomain &s = *owned[i];
        for (unsigned int v = 0; v < s.body_vertex.size(); ++v)
          if (lowest[s.body.index][s.body_vertex[v]] == s.global_index)
            for (unsigned int c = 0; c < 3; ++c)
              result[s.body.index][s.body_vertex[v]][c] = u[i][s.vertex_dofs[v][c]];
      }
    for (auto &r : result)
      MPITools::sum_in_place(comm, reinterpret_cast<double *>(r.data()), 3 * r.size());
    return result;
  }

  std::vector<Tensor<1, 3>>
  solve_monolithic(const Body &body, const Mapping<3> &mapping, const FiniteElement<3> &fe)
  {
    DoFHandler<3> dof_handler(body.mesh);
    dof_handler.distribute_dofs(fe);
    SparsityPattern      sparsity;
    SparseMatrix<double> K;
    Vector<double>       f;
    assemble_elasticity(dof_handler, mapping, body.parameters, sparsity, K, f);
    const auto                         vertex_dofs = vertex_dof_indices(dof_handler);
    std::vector<std::optional<double>> prescribed(dof_handler.n_dofs());
    for (const auto &[v, value] : body.prescribed)
      for (unsigned int c = 0; c < 3; ++c)
        prescribed[vertex_dofs[v][c]] = value[c];
    eliminate_prescribed_dofs(prescribed, K, f);
    CholmodSolver solver;
    solver.factorize(K);
    solver.solve(f);
    std::vector<Tensor<1, 3>> u(body.mesh.n_vertices());
    for (unsigned int v = 0; v < u.size(); ++v)
      if (vertex_dofs[v][0] != numbers::invalid_dof_index)
        for (unsigned int c = 0; c < 3; ++c)
          u[v][c] = f[vertex_dofs[v][c]];
    return u;
  }

  std::vector<ForceBalance>
  compute_force_balance(const MPI_Comm                     comm,
                        const unsigned int                 n_bodies,
                        const std::vector<Subdomain *>    &owned,
                        const std::vector<Vector<double>> &u,
                        const Mapping<3>                  &mapping,
                        const std::vector<Tensor<1, 3>>   &contact_forces)
  {
    std::vector<double> sums(6 * n_bodies, 0.0);
    for (unsigned int i = 0; i < owned.size(); ++i)
      {
        const Subdomain     &s = *owned[i];
        SparsityPattern      sparsity;
        SparseMatrix<double> K;
        Vector<double>       f, r(s.dof_handler.n_dofs());
        assemble_elasticity(s.dof_handler, mapping, s.body.parameters, sparsity, K, f);
        K.vmult(r, u[i]);
        r -= f;
        for (unsigned int d = 0; d < f.size(); ++d)
          {
            const unsigned int c = s.dof_component[d];
            sums[6 * s.body.index + c] += f[d];
            if (s.prescribed[d])
              sums[6 * s.body.index + 3 + c] += r[d];
          }
      }
    MPITools::sum_in_place(comm, sums.data(), sums.size());
    std::vector<ForceBalance> balance(n_bodies);
    for (unsigned int b = 0; b < n_bodies; ++b)
      {
        for (unsigned int c = 0; c < 3; ++c)
          {
            balance[b].applied[c] = sums[6 * b + c];
            balance[b].support[c] = sums[6 * b + 3 + c];
          }
        if (b < contact_forces.size())
          balance[b].contact = contact_forces[b];
        const auto  &fb    = balance[b];
        const double scale = std::max({fb.applied.norm(), fb.support.norm(), fb.contact.norm()});
        balance[b].relative_imbalance =
          scale > 0 ? (fb.applied + fb.support + fb.contact).norm() / scale : 0.0;
      }
    return balance;
  }
} // namespace FetiContact
