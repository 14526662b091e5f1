#pragma once

#include <deal.II/grid/tria.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <feticontact/scene/body_parameters.h>
#include <feticontact/scene/decomposition.h>
#include <feticontact/scene/part_cells.h>

#include <array>
#include <map>
#include <optional>

namespace FetiContact
{
  /**
   * The rigid motions of a body that its prescribed displacements leave free, as combinations
   * of the six motions φ_i(x) = e_i (i < 3) and e_{i−3} × (x − x̄)/L (i ≥ 3), x̄ the centroid of
   * the vertices and L the diagonal of their bounding box: the columns of @p coefficients
   * (6 × r, orthonormal), r = 0 for a held body.
   */
  struct FreeRigidMotions
  {
    dealii::Point<3>           centre;
    double                     length = 1;
    dealii::FullMatrix<double> coefficients;

    /** r: the number of free motions. */
    unsigned int
    n() const
    {
      return coefficients.n();
    }

    /** v_j(x), the free motion @p j at @p x. */
    dealii::Tensor<1, 3>
    value(const unsigned int j, const dealii::Point<3> &x) const;
  };

  /**
   * One elastic body of the scene: its parameters (with boundary selectors resolved against its
   * mesh), the undecomposed tetrahedral mesh, the prescribed displacements per mesh vertex (Γ_u)
   * and the partition of its cells into FETI subdomains. Every MPI rank holds every body.
   */
  class Body
  {
  public:
    /** Prescribed components of the displacement of one vertex. */
    using Prescribed = std::array<std::optional<double>, 3>;

    Body(const Parameters::Body &parameters, const unsigned int index);

    /** Creates the mesh, resolves the boundary selectors, collects Γ_u and partitions. */
    void
    setup();

    /**
     * Checks that the prescribed displacements hold the body: no rigid motion is left free.
     * (Contact may hold a body too; this is for scenes without contact.)
     */
    void
    check_held() const;

    /**
     * The rigid motions left free by the prescribed displacements: the motions whose norm on
     * the prescribed DoFs is below 1e-5 of their norm on all DoFs (the kernel of the stiffness
     * matrix with those DoFs eliminated).
     */
    FreeRigidMotions
    free_rigid_motions() const;

    /**
     * The work of the body's loads (tractions and volume force) on each free rigid motion:
     * ∫_Γ t·v_j + ∫_Ω b·v_j, exact for the linear motions.
     */
    dealii::Vector<double>
    load_work(const FreeRigidMotions &motions) const;

    /**
     * The cells of part @p part, for the subdomain built on them; @p parts_of_vertex is
     * parts_of_vertices() of this body.
     */
    PartCells
    part_cells(const unsigned int                            part,
               const std::vector<std::vector<unsigned int>> &parts_of_vertex) const;

    /** The same, with parts_of_vertices() computed for this one part (a pass over the mesh). */
    PartCells
    part_cells(const unsigned int part) const;

    /** The number of unknowns of the undecomposed body without prescribed DoFs. */
    unsigned int
    n_free_dofs() const;

    Parameters::Body                   parameters;
    unsigned int                       index;
    dealii::Triangulation<3>           mesh;
    std::map<unsigned int, Prescribed> prescribed; ///< by mesh vertex index
    CellPartition                      partition;
    /**
     * The active cells of every part of @p partition, in the order of the active cells. Listed
     * once in setup(), so that building a subdomain visits its own cells only (not every cell
     * of the body once per subdomain, which is quadratic in the number of subdomains).
     */
    std::vector<std::vector<dealii::Triangulation<3>::active_cell_iterator>> cells_of_part;
  };
} // namespace FetiContact
