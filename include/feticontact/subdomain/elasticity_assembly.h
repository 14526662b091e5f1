#pragma once

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <feticontact/scene/body_parameters.h>

#include <array>
#include <optional>
#include <vector>

namespace FetiContact
{
  /**
   * P1 linear elasticity on a tetrahedral mesh: the stiffness matrix
   * K_ij = ∫ λ div φ_i div φ_j + 2μ ε(φ_i):ε(φ_j) dx and the load vector
   * f_i = ∫ b·φ_i dx + ∫_Γt t·φ_i ds of the body's material, volume force and tractions.
   * Used alike for a FETI subdomain and for the undecomposed body (verification).
   */
  void
  assemble_elasticity(const dealii::DoFHandler<3>  &dof_handler,
                      const dealii::Mapping<3>     &mapping,
                      const Parameters::Body       &body,
                      dealii::SparsityPattern      &sparsity,
                      dealii::SparseMatrix<double> &K,
                      dealii::Vector<double>       &f);

  /**
   * For every vertex of the DoFHandler's mesh, the DoF indices of its three displacement
   * components (P1: one DoF per vertex and component).
   */
  std::vector<std::array<dealii::types::global_dof_index, 3>>
  vertex_dof_indices(const dealii::DoFHandler<3> &dof_handler);

  /**
   * Eliminates prescribed DoFs from K u = f, keeping the size: for a prescribed DoF d with value
   * ū_d, f ← f − K e_d ū_d on the other rows, row and column d of K are zeroed except the
   * diagonal, and f_d = K_dd ū_d. The solution then has u_d = ū_d, and the kernel of K is the
   * set of rigid motions vanishing on the prescribed DoFs.
   */
  void
  eliminate_prescribed_dofs(const std::vector<std::optional<double>> &prescribed,
                            dealii::SparseMatrix<double>             &K,
                            dealii::Vector<double>                   &f);
} // namespace FetiContact
