#pragma once

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <feticontact/local_solvers/local_solver.h>
#include <feticontact/scene/body.h>

#include <array>
#include <memory>
#include <optional>
#include <vector>

namespace FetiContact
{
  /**
   * One FETI subdomain Ω_i: the cells of one part of a body's partition with their own
   * Triangulation, DoFHandler (P1 vector elements, FE_SimplexP(1)^3 with MappingFE), the
   * stiffness matrix K_i and load vector f_i, the rigid body modes R_i (an orthonormal basis of
   * ker K_i) and the generalized inverse K_i⁺.
   *
   * With primal Dirichlet treatment the prescribed DoFs are eliminated in K_i and f_i (so a
   * subdomain on a clamped face has no kernel); with TFETI they stay free and are B_E rows.
   * K_i⁺ = [K̃_rr⁻¹ 0; 0 0]: the DoFs chosen by select_kernel_fixing_dofs() are fixed to zero
   * and the rest is factorized by the local solver backend (rank(K̃_rr) = rank(K_i), so
   * K_i K_i⁺ K_i = K_i).
   */
  class Subdomain
  {
  public:
    /**
     * Builds the mesh of the part of @p body whose cells @p cells describes and its DoFs;
     * @p eliminate_prescribed selects the primal Dirichlet treatment.
     */
    Subdomain(const Body                     &body,
              PartCells                     &&cells,
              const unsigned int              global_index,
              const bool                      eliminate_prescribed,
              const dealii::FiniteElement<3> &fe);

    /** Assembles K_i and f_i (and eliminates prescribed DoFs for the primal treatment). */
    void
    assemble(const dealii::Mapping<3> &mapping);

    /** Computes R_i and factorizes the regularized K_i with the backend @p local_solver. */
    void
    factorize(const std::string &local_solver);

    /**
     * K̃_i: K_i with the rows and columns of the kernel-fixing DoFs replaced by their diagonal,
     * the symmetric positive definite matrix that factorize() hands to the local solver (the
     * fixing DoFs are those of the last factorize()).
     */
    dealii::SparseMatrix<double>
    regularized_stiffness() const;

    /** x ← K_i⁺ x. */
    void
    apply_generalized_inverse(dealii::Vector<double> &x) const;

    /** The backend that holds the factor of K̃_i (nullptr before factorize()). */
    LocalSolver *
    local_solver()
    {
      return solver.get();
    }

    /** The number of unknowns (without eliminated prescribed DoFs). */
    unsigned int
    n_unknowns() const;

    const Body        &body;
    const unsigned int part;
    const unsigned int global_index;
    const bool         prescribed_eliminated;

    dealii::Triangulation<3> mesh;
    dealii::DoFHandler<3>    dof_handler;

    /** The subdomains that hold vertex @p v (this one among them), in increasing order. */
    std::vector<unsigned int>
    holders(const unsigned int v) const;

    /** The lowest-numbered subdomain that holds vertex @p v: the one that reports it. */
    unsigned int
    lowest_holder(const unsigned int v) const
    {
      return global_index - part + holder_parts[holder_start[v]];
    }

    /**
     * The vertices that this subdomain reports (those whose lowest holder it is) as pairs
     * (body vertex, own vertex), by body vertex: each vertex of the body is reported once.
     */
    std::vector<std::pair<unsigned int, unsigned int>>
    reported_vertices() const;

    /** Body-mesh vertex of each vertex of this subdomain's mesh. */
    std::vector<unsigned int> body_vertex;
    /** DoFs of each vertex of this subdomain's mesh, by component. */
    std::vector<std::array<dealii::types::global_dof_index, 3>> vertex_dofs;
    /** Per DoF: its vertex (of this subdomain's mesh) and its component. */
    std::vector<unsigned int> dof_vertex, dof_component;
    /** Per DoF: the prescribed value where Γ_u prescribes one (body's data). */
    std::vector<std::optional<double>> prescribed;

    dealii::SparsityPattern      sparsity;
    dealii::SparseMatrix<double> K;
    dealii::Vector<double>       f;
    /** Orthonormal basis of ker K_i, n_dofs × n_modes. */
    dealii::FullMatrix<double> R;
    /** DoFs fixed to zero in K_i⁺. */
    std::vector<unsigned int> kernel_fixing_dofs;

  private:
    /** Per vertex: the parts of the body that hold it, increasing (CSR, as in PartCells). */
    std::vector<unsigned int> holder_start, holder_parts;

    std::unique_ptr<LocalSolver> solver;
  };
} // namespace FetiContact
