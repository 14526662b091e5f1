#include <deal.II/grid/tria_description.h>

#include <feticontact/subdomain/elasticity_assembly.h>
#include <feticontact/subdomain/rigid_body_modes.h>
#include <feticontact/subdomain/subdomain.h>

#include <algorithm>
#include <map>

namespace FetiContact
{
  using namespace dealii;

  Subdomain::Subdomain(const Body             &body,
                       PartCells             &&cells,
                       const unsigned int      global_index,
                       const bool              eliminate_prescribed,
                       const FiniteElement<3> &fe)
    : body(body)
    , part(cells.part)
    , global_index(global_index)
    , prescribed_eliminated(eliminate_prescribed)
    , body_vertex(std::move(cells.body_vertex))
    , holder_start(std::move(cells.holder_start))
    , holder_parts(std::move(cells.holder_parts))
  {
    // The sub-mesh: boundary ids carried over; faces shared with other parts become interface
    // faces.
    std::vector<CellData<3>> cell_data(cells.cells.size(), CellData<3>(4));
    for (unsigned int c = 0; c < cells.cells.size(); ++c)
      {
        std::copy(cells.cells[c].begin(), cells.cells[c].end(), cell_data[c].vertices.begin());
        cell_data[c].material_id = body.index;
      }
    mesh.create_triangulation(cells.points, cell_data, SubCellData());
    const std::map<std::array<unsigned int, 3>, types::boundary_id> boundary_faces(
      cells.boundary_faces.begin(), cells.boundary_faces.end());
    for (const auto &cell : mesh.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          {
            std::array<unsigned int, 3> key;
            for (unsigned int v = 0; v < 3; ++v)
              key[v] = face->vertex_index(v);
            std::sort(key.begin(), key.end());
            const auto it = boundary_faces.find(key);
            face->set_boundary_id(it == boundary_faces.end() ? interface_boundary_id : it->second);
          }

    dof_handler.reinit(mesh);
    dof_handler.distribute_dofs(fe);
    vertex_dofs = vertex_dof_indices(dof_handler);
    dof_vertex.resize(dof_handler.n_dofs());
    dof_component.resize(dof_handler.n_dofs());
    prescribed.resize(dof_handler.n_dofs());
    for (unsigned int v = 0; v < vertex_dofs.size(); ++v)
      {
        const auto it = body.prescribed.find(body_vertex[v]);
        for (unsigned int c = 0; c < 3; ++c)
          {
            const auto dof     = vertex_dofs[v][c];
            dof_vertex[dof]    = v;
            dof_component[dof] = c;
            if (it != body.prescribed.end())
              prescribed[dof] = it->second[c];
          }
      }
  }

  std::vector<unsigned int>
  Subdomain::holders(const unsigned int v) const
  {
    std::vector<unsigned int> result(holder_parts.begin() + holder_start[v],
                                     holder_parts.begin() + holder_start[v + 1]);
    for (unsigned int &h : result)
      h += global_index - part;
    return result;
  }

  std::vector<std::pair<unsigned int, unsigned int>>
  Subdomain::reported_vertices() const
  {
    std::vector<std::pair<unsigned int, unsigned int>> vertices;
    for (unsigned int v = 0; v < body_vertex.size(); ++v)
      if (lowest_holder(v) == global_index)
        vertices.emplace_back(body_vertex[v], v);
    std::sort(vertices.begin(), vertices.end());
    return vertices;
  }

  void
  Subdomain::assemble(const Mapping<3> &mapping)
  {
    assemble_elasticity(dof_handler, mapping, body.parameters, sparsity, K, f);
    if (prescribed_eliminated)
      eliminate_prescribed_dofs(prescribed, K, f);
  }

  void
  Subdomain::factorize(const std::string &local_solver)
  {
    std::vector<Point<3>> points(dof_vertex.size());
    std::vector<bool>     fixed(dof_vertex.size(), false);
    for (unsigned int i = 0; i < dof_vertex.size(); ++i)
      {
        points[i] = mesh.get_vertices()[dof_vertex[i]];
        fixed[i]  = prescribed_eliminated && prescribed[i].has_value();
      }
    R                  = rigid_body_modes(points, dof_component, fixed);
    kernel_fixing_dofs = select_kernel_fixing_dofs(R);
    solver             = LocalSolver::create(local_solver);
    solver->factorize(regularized_stiffness());
  }

  SparseMatrix<double>
  Subdomain::regularized_stiffness() const
  {
    SparseMatrix<double> K_regularized(sparsity);
    K_regularized.copy_from(K);
    std::vector<bool> fix(K.m(), false);
    for (const unsigned int d : kernel_fixing_dofs)
      fix[d] = true;
    for (unsigned int i = 0; i < K.m(); ++i)
      for (auto it = K_regularized.begin(i); it != K_regularized.end(i); ++it)
        if (it->column() != i && (fix[i] || fix[it->column()]))
          it->value() = 0;
    return K_regularized;
  }

  void
  Subdomain::apply_generalized_inverse(Vector<double> &x) const
  {
    for (const unsigned int d : kernel_fixing_dofs)
      x[d] = 0;
    solver->solve(x);
    for (const unsigned int d : kernel_fixing_dofs)
      x[d] = 0;
  }

  unsigned int
  Subdomain::n_unknowns() const
  {
    if (!prescribed_eliminated)
      return dof_handler.n_dofs();
    return std::count_if(prescribed.begin(), prescribed.end(), [](const auto &p) {
      return !p.has_value();
    });
  }
} // namespace FetiContact
