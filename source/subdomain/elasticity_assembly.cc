#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <feticontact/subdomain/elasticity_assembly.h>

namespace FetiContact
{
  using namespace dealii;

  void
  assemble_elasticity(const DoFHandler<3>    &dof_handler,
                      const Mapping<3>       &mapping,
                      const Parameters::Body &body,
                      SparsityPattern        &sparsity,
                      SparseMatrix<double>   &K,
                      Vector<double>         &f)
  {
    DynamicSparsityPattern dsp(dof_handler.n_dofs());
    DoFTools::make_sparsity_pattern(dof_handler, dsp);
    sparsity.copy_from(dsp);
    K.reinit(sparsity);
    f.reinit(dof_handler.n_dofs());

    const auto            &fe = dof_handler.get_fe();
    const QGaussSimplex<3> quadrature(1); // P1: constant strains, linear test functions
    const QGaussSimplex<3> load_quadrature(2);
    const QGaussSimplex<2> face_quadrature(2);
    FEValues<3>            fe_values(mapping, fe, quadrature, update_gradients | update_JxW_values);
    FEValues<3>     load_values(mapping, fe, load_quadrature, update_values | update_JxW_values);
    FEFaceValues<3> face_values(mapping, fe, face_quadrature, update_values | update_JxW_values);

    const double lambda           = body.material.lambda();
    const double mu               = body.material.mu();
    const auto  &bc               = body.boundary_conditions;
    const bool   has_volume_force = bc.volume_force.norm() > 0;

    const unsigned int                   n = fe.n_dofs_per_cell();
    FullMatrix<double>                   cell_matrix(n, n);
    Vector<double>                       cell_rhs(n);
    std::vector<types::global_dof_index> dofs(n);
    const FEValuesExtractors::Vector     displacement(0);
    std::vector<SymmetricTensor<2, 3>>   eps(n);
    std::vector<double>                  div(n);

    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell_matrix = 0;
        cell_rhs    = 0;
        fe_values.reinit(cell);
        for (const unsigned int q : fe_values.quadrature_point_indices())
          {
            for (unsigned int i = 0; i < n; ++i)
              {
                eps[i] = fe_values[displacement].symmetric_gradient(i, q);
                div[i] = trace(eps[i]);
              }
            const double JxW = fe_values.JxW(q);
            for (unsigned int i = 0; i < n; ++i)
              for (unsigned int j = 0; j <= i; ++j)
                cell_matrix(i, j) += (lambda * div[i] * div[j] + 2 * mu * (eps[i] * eps[j])) * JxW;
          }
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = i + 1; j < n; ++j)
            cell_matrix(i, j) = cell_matrix(j, i);

        if (has_volume_force)
          {
            load_values.reinit(cell);
            for (const unsigned int q : load_values.quadrature_point_indices())
              for (unsigned int i = 0; i < n; ++i)
                {
                  const unsigned int c = fe.system_to_component_index(i).first;
                  cell_rhs(i) +=
                    bc.volume_force[c] * load_values.shape_value(i, q) * load_values.JxW(q);
                }
          }
        for (const unsigned int face_no : cell->face_indices())
          if (cell->face(face_no)->at_boundary())
            for (const auto &traction : bc.tractions)
              if (traction.boundary.contains(*cell->face(face_no)))
                {
                  face_values.reinit(cell, face_no);
                  for (const unsigned int q : face_values.quadrature_point_indices())
                    for (unsigned int i = 0; i < n; ++i)
                      {
                        const unsigned int c = fe.system_to_component_index(i).first;
                        cell_rhs(i) +=
                          traction.value[c] * face_values.shape_value(i, q) * face_values.JxW(q);
                      }
                }
        cell->get_dof_indices(dofs);
        for (unsigned int i = 0; i < n; ++i)
          {
            for (unsigned int j = 0; j < n; ++j)
              K.add(dofs[i], dofs[j], cell_matrix(i, j));
            f(dofs[i]) += cell_rhs(i);
          }
      }
  }

  std::vector<std::array<types::global_dof_index, 3>>
  vertex_dof_indices(const DoFHandler<3> &dof_handler)
  {
    const auto                                         &fe = dof_handler.get_fe();
    std::vector<std::array<types::global_dof_index, 3>> result(
      dof_handler.get_triangulation().n_vertices(),
      {{numbers::invalid_dof_index, numbers::invalid_dof_index, numbers::invalid_dof_index}});
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell->get_dof_indices(dofs);
        for (const unsigned int v : cell->vertex_indices())
          for (unsigned int c = 0; c < 3; ++c)
            result[cell->vertex_index(v)][c] = dofs[fe.component_to_system_index(c, v)];
      }
    return result;
  }

  void
  eliminate_prescribed_dofs(const std::vector<std::optional<double>> &prescribed,
                            SparseMatrix<double>                     &K,
                            Vector<double>                           &f)
  {
    for (unsigned int i = 0; i < K.m(); ++i)
      for (auto it = K.begin(i); it != K.end(i); ++it)
        {
          const unsigned int j = it->column();
          if (j == i)
            continue;
          if (prescribed[j] && !prescribed[i])
            f(i) -= it->value() * (*prescribed[j]);
          if (prescribed[i] || prescribed[j])
            it->value() = 0;
        }
    for (unsigned int i = 0; i < K.m(); ++i)
      if (prescribed[i])
        f(i) = K.diag_element(i) * (*prescribed[i]);
  }
} // namespace FetiContact
