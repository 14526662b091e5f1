#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <feticontact/postprocessing/fclib_export.h>
#include <feticontact/subdomain/elasticity_assembly.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#ifdef FETICONTACT_WITH_FCLIB
// fclib.h declares its C functions without extern "C".
extern "C"
{
#  include <fclib.h>
}
#endif

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    /** The free DoFs of one body: global index in v per vertex and component, or −1. */
    struct BodyDofs
    {
      std::vector<std::array<int, 3>> free_index;
    };
  } // namespace

  FclibProblem
  assemble_fclib_problem(const std::vector<std::unique_ptr<Body>>     &bodies,
                         const std::vector<ContactNode>               &nodes,
                         const std::vector<ContactNodeResult>         &results,
                         const std::vector<std::vector<Tensor<1, 3>>> &vertex_u,
                         const Mapping<3>                             &mapping,
                         const FiniteElement<3>                       &fe)
  {
    FclibProblem problem;
    // Rows of M as (column, value), global free numbering; M is symmetric, so its compressed
    // columns are its compressed rows.
    std::vector<std::vector<std::pair<int, double>>> rows;
    std::vector<BodyDofs>                            body_dofs(bodies.size());
    int                                              offset = 0;
    for (const auto &body : bodies)
      {
        DoFHandler<3> dof_handler(body->mesh);
        dof_handler.distribute_dofs(fe);
        SparsityPattern      sparsity;
        SparseMatrix<double> K;
        Vector<double>       f;
        assemble_elasticity(dof_handler, mapping, body->parameters, sparsity, K, f);
        const auto vertex_dofs = vertex_dof_indices(dof_handler);

        // ū per DoF (prescribed components) and the free numbering.
        std::vector<std::optional<double>> prescribed(dof_handler.n_dofs());
        for (const auto &[vertex, value] : body->prescribed)
          for (unsigned int c = 0; c < 3; ++c)
            prescribed[vertex_dofs[vertex][c]] = value[c];
        std::vector<int> free(dof_handler.n_dofs(), -1);
        for (types::global_dof_index d = 0; d < free.size(); ++d)
          if (!prescribed[d])
            free[d] = offset++;
        auto &index = body_dofs[body->index].free_index;
        index.assign(vertex_dofs.size(), {{-1, -1, -1}});
        for (unsigned int v = 0; v < vertex_dofs.size(); ++v)
          if (vertex_dofs[v][0] != numbers::invalid_dof_index)
            for (unsigned int c = 0; c < 3; ++c)
              index[v][c] = free[vertex_dofs[v][c]];

        rows.resize(offset);
        problem.f.resize(offset);
        problem.v.resize(offset);
        for (types::global_dof_index d = 0; d < free.size(); ++d)
          {
            if (free[d] < 0)
              continue;
            double rhs = f[d];
            for (auto entry = K.begin(d); entry != K.end(d); ++entry)
              {
                const auto j = entry->column();
                if (free[j] >= 0)
                  rows[free[d]].emplace_back(free[j], entry->value());
                else
                  rhs -= entry->value() * *prescribed[j];
              }
            problem.f[free[d]] = rhs;
          }
        for (unsigned int v = 0; v < vertex_dofs.size(); ++v)
          for (unsigned int c = 0; c < 3; ++c)
            if (index[v][c] >= 0)
              problem.v[index[v][c]] = vertex_u[body->index][v][c];
      }

    auto &M     = problem.M;
    M.n_rows    = offset;
    M.n_columns = offset;
    M.column_start.push_back(0);
    for (auto &row : rows)
      {
        std::sort(row.begin(), row.end());
        for (const auto &[j, value] : row)
          {
            M.row.push_back(j);
            M.value.push_back(value);
          }
        M.column_start.push_back(M.row.size());
      }

    // H and w, one frame [n, t1, t2] per contact node: û_c = −e_c·(u_slave − u_master) (+ d).
    auto &H     = problem.H;
    H.n_rows    = offset;
    H.n_columns = 3 * nodes.size();
    H.column_start.push_back(0);
    problem.w.assign(3 * nodes.size(), 0.0);
    problem.r.assign(3 * nodes.size(), 0.0);
    problem.mu.resize(nodes.size());
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        const auto                               &node = nodes[k];
        const std::array<const Tensor<1, 3> *, 3> frame{{&node.n, &node.t1, &node.t2}};
        problem.mu[k]        = node.friction;
        problem.w[3 * k]     = node.gap;
        problem.r[3 * k]     = results[k].lambda_N;
        problem.r[3 * k + 1] = results[k].lambda_T[0];
        problem.r[3 * k + 2] = results[k].lambda_T[1];
        // (body, vertex, sign) of the slave and of the master.
        std::vector<std::tuple<unsigned int, unsigned int, double>> ends{
          {node.body, node.vertex, -1.0}};
        if (node.master)
          ends.emplace_back(node.master->first, node.master->second, 1.0);
        for (unsigned int c = 0; c < 3; ++c)
          {
            std::vector<std::pair<int, double>> column;
            for (const auto &[b, vertex, sign] : ends)
              for (unsigned int d = 0; d < 3; ++d)
                {
                  const double coefficient = sign * (*frame[c])[d];
                  const int    i           = body_dofs[b].free_index[vertex][d];
                  if (i >= 0)
                    {
                      if (coefficient != 0)
                        column.emplace_back(i, coefficient);
                    }
                  else
                    problem.w[3 * k + c] += coefficient * *bodies[b]->prescribed.at(vertex)[d];
                }
            std::sort(column.begin(), column.end());
            for (const auto &[i, value] : column)
              {
                H.row.push_back(i);
                H.value.push_back(value);
              }
            H.column_start.push_back(H.row.size());
          }
      }

    // u = Hᵀ v + w.
    problem.u = problem.w;
    for (int j = 0; j < H.n_columns; ++j)
      for (int p = H.column_start[j]; p < H.column_start[j + 1]; ++p)
        problem.u[j] += H.value[p] * problem.v[H.row[p]];
    return problem;
  }

  bool
  fclib_available()
  {
#ifdef FETICONTACT_WITH_FCLIB
    return true;
#else
    return false;
#endif
  }

  void
  write_fclib(const std::string  &file,
              const FclibProblem &problem,
              const std::string  &title,
              const std::string  &description)
  {
#ifdef FETICONTACT_WITH_FCLIB
    // libfclib takes non-const pointers but only reads through them when writing.
    auto as_fclib = [](const FclibProblem::CompressedColumns &A) {
      fclib_matrix m{};
      m.nzmax = static_cast<int>(A.value.size());
      m.m     = A.n_rows;
      m.n     = A.n_columns;
      m.p     = const_cast<int *>(A.column_start.data());
      m.i     = const_cast<int *>(A.row.data());
      m.x     = const_cast<double *>(A.value.data());
      m.nz    = -1; // compressed columns
      m.info  = nullptr;
      return m;
    };
    fclib_matrix M = as_fclib(problem.M), H = as_fclib(problem.H);
    std::string  math_info =
      "M symmetric positive semidefinite (definite when every body is held by prescribed "
      "displacements); quasi-static: v, u are displacements, r forces";
    fclib_info   info{const_cast<char *>(title.c_str()),
                    const_cast<char *>(description.c_str()),
                    math_info.data()};
    fclib_global global{};
    global.M        = &M;
    global.H        = &H;
    global.G        = nullptr;
    global.mu       = const_cast<double *>(problem.mu.data());
    global.f        = const_cast<double *>(problem.f.data());
    global.b        = nullptr;
    global.w        = const_cast<double *>(problem.w.data());
    global.spacedim = 3;
    global.info     = &info;

    // libfclib refuses to write into a file that holds a problem already.
    std::filesystem::remove(file);
    if (fclib_write_global(&global, file.c_str()) != 1)
      throw std::runtime_error("FCLIB: writing the problem to " + file + " failed");
    fclib_solution solution{const_cast<double *>(problem.v.data()),
                            const_cast<double *>(problem.u.data()),
                            const_cast<double *>(problem.r.data()),
                            nullptr};
    if (fclib_write_solution(&solution, file.c_str()) != 1)
      throw std::runtime_error("FCLIB: writing the solution to " + file + " failed");
#else
    (void)problem;
    (void)title;
    (void)description;
    throw std::runtime_error("cannot write " + file +
                             ": this build has no FCLIB (install libfclib-dev, then run cmake "
                             "again)");
#endif
  }
} // namespace FetiContact
