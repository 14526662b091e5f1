#pragma once

#include <deal.II/base/point.h>
#include <deal.II/lac/full_matrix.h>

#include <vector>

namespace FetiContact
{
  /**
   * An orthonormal basis (columns) of the rigid body motions u(x) = a + ω × (x − x̄) of a set of
   * DoFs (each a point and a component) that vanish on the DoFs marked @p fixed: the kernel of
   * the stiffness matrix of a body or subdomain whose prescribed DoFs are eliminated. x̄ is the
   * centroid of the points. With nothing fixed the result has six columns (three translations,
   * three rotations about x̄); a clamped face leaves none.
   *
   * The restriction of the six rigid motions to the fixed DoFs is a |D| × 6 matrix R_D; the
   * kernel is spanned by the motions whose coefficients lie in the null space of R_Dᵀ R_D
   * (eigenvalues below 1e-10 of the largest possible value 1, the columns being orthonormal).
   */
  dealii::FullMatrix<double>
  rigid_body_modes(const std::vector<dealii::Point<3>> &dof_points,
                   const std::vector<unsigned int>     &dof_components,
                   const std::vector<bool>             &fixed);

  /**
   * Chooses R.n() rows of @p R (DoFs) such that R restricted to them is nonsingular, by pivoted
   * Gram–Schmidt on the rows (largest remaining row first): fixing these DoFs removes the kernel
   * and gives the generalized inverse K⁺ = [K_rr⁻¹ 0; 0 0].
   */
  std::vector<unsigned int>
  select_kernel_fixing_dofs(const dealii::FullMatrix<double> &R);

  /**
   * Eigen decomposition A = V diag(w) Vᵀ of a small symmetric matrix, eigenvalues increasing
   * (LAPACK's dsyevx through dealii::LAPACKFullMatrix).
   */
  void
  symmetric_eigen(const dealii::FullMatrix<double> &A,
                  std::vector<double>              &w,
                  dealii::FullMatrix<double>       &V);
} // namespace FetiContact
