#include <deal.II/grid/tria_description.h>

#include <feticontact/subdomain/elasticity_assembly.h>
#include <feticontact/subdomain/rigid_body_modes.h>
#include <feticontact/subdomain/subdomain.h>

#include <algorithm>
#include <map>
#include <unordered_map>

namespace FetiContact
{
  using namespace dealii;

  Subdomain::Subdomain(const Body             &body,
                       const unsigned int      part,
                       const unsigned int      global_index,
                       const bool              eliminate_prescribed,
                       const FiniteElement<3> &fe)
    : body(body)
    , part(part)
    , global_index(global_index)
    , prescribed_eliminated(eliminate_prescribed)
  {
    // The sub-mesh: cells of this part, vertices renumbered, boundary ids carried over; faces
    // shared with other parts become interface faces.
    // (A map, not a vector over all vertices of the body: that would be quadratic in the number
    // of subdomains.)
    std::unordered_map<unsigned int, unsigned int>            local_vertex;
    std::vector<CellData<3>>                                  cells;
    std::vector<Point<3>>                                     vertices;
    std::map<std::array<unsigned int, 3>, types::boundary_id> boundary_faces;
    for (const auto &cell : body.cells_of_part[part])
      {
        CellData<3> data(4);
        for (const unsigned int v : cell->vertex_indices())
          {
            const unsigned int gv          = cell->vertex_index(v);
            const auto [entry, first_seen] = local_vertex.emplace(gv, vertices.size());
            if (first_seen)
              {
                vertices.push_back(cell->vertex(v));
                body_vertex.push_back(gv);
              }
            data.vertices[v] = entry->second;
          }
        data.material_id = body.index;
        cells.push_back(data);
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              std::array<unsigned int, 3> key;
              for (unsigned int v = 0; v < 3; ++v)
                key[v] = face->vertex_index(v);
              std::sort(key.begin(), key.end());
              boundary_faces[key] = face->boundary_id();
            }
      }
    mesh.create_triangulation(vertices, cells, SubCellData());
    for (const auto &cell : mesh.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          {
            std::array<unsigned int, 3> key;
            for (unsigned int v = 0; v < 3; ++v)
              key[v] = body_vertex[face->vertex_index(v)];
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
