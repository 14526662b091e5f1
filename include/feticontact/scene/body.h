#pragma once

#include <deal.II/grid/tria.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <feticontact/scene/body_parameters.h>
#include <feticontact/scene/decomposition.h>
#include <feticontact/scene/lattice_parts.h>
#include <feticontact/scene/part_cells.h>

#include <array>
#include <functional>
#include <map>
#include <mpi.h>
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

    /**
     * The free motions as text for a message: each a translation along a direction, or a
     * rotation about an axis through a point (with a translation along that axis if it has one),
     * e.g. "translation along (1, 0, 0); rotation about (0, 0, 1) through (0.5, 0.5, 0)".
     */
    std::string
    text() const;
  };

  /**
   * One elastic body of the scene: its parameters (with boundary selectors resolved against its
   * mesh), its tetrahedral mesh, the prescribed displacements per vertex (Γ_u) and the partition
   * of its cells into FETI subdomains.
   *
   * The mesh is the cells this rank holds: every cell of the body on one rank, or, distributed
   * over the ranks of a communicator, the cells of the parts this rank owns. Every rank then makes
   * the cells of its own parts where the parts are blocks of a generated box (LatticeParts);
   * otherwise rank 0 creates the whole mesh and partitions it, sends every rank the cells of its
   * parts (PartCells) and keeps only its own. The vertices and cells keep the numbers they have in
   * the whole mesh (body_vertex(), body_cell()); what concerns the whole body (selectors, Γ_u along
   * the interfaces, rigid motions, loads, counts) is reduced over the ranks.
   */
  class Body
  {
  public:
    /** Prescribed components of the displacement of one vertex. */
    using Prescribed = std::array<std::optional<double>, 3>;

    Body(const Parameters::Body &parameters, const unsigned int index);

    /**
     * Creates the mesh, partitions it, resolves the boundary selectors and collects Γ_u, on
     * this rank alone (the mesh is whole).
     */
    void
    setup();

    /**
     * Creates the mesh and its partition: on rank 0 of @p comm, which tells the others the number
     * of cells of every part (on no rank for the blocks of a generated box, whose parts every
     * rank knows). Collective.
     */
    void
    create_and_partition(const MPI_Comm comm);

    /**
     * Distributed: every rank makes its mesh of the cells of the parts that @p owner (a part's
     * rank) gives it, which it generates (blocks of a box) or receives from rank 0. On one rank:
     * nothing. Collective.
     */
    void
    distribute(const std::function<unsigned int(unsigned int)> &owner);

    /** Resolves the boundary selectors and collects Γ_u. Collective. */
    void
    set_up_boundary();

    /**
     * Checks that the prescribed displacements hold the body: no rigid motion is left free.
     * (Contact may hold a body too; this is for scenes without contact.) Collective.
     */
    void
    check_held() const;

    /**
     * The rigid motions left free by the prescribed displacements: the motions whose norm on
     * the prescribed DoFs is below 1e-5 of their norm on all DoFs (the kernel of the stiffness
     * matrix with those DoFs eliminated). Collective.
     */
    FreeRigidMotions
    free_rigid_motions() const;

    /**
     * The work of the body's loads (tractions and volume force) on each free rigid motion:
     * ∫_Γ t·v_j + ∫_Ω b·v_j, exact for the linear motions. Collective.
     */
    dealii::Vector<double>
    load_work(const FreeRigidMotions &motions) const;

    /**
     * The cells of part @p part, which this rank holds, for the subdomain built on them;
     * @p parts_of_vertex is parts_of_mesh_vertices().
     */
    PartCells
    part_cells(const unsigned int                            part,
               const std::vector<std::vector<unsigned int>> &parts_of_vertex) const;

    /** The same, with parts_of_mesh_vertices() computed for this one part. */
    PartCells
    part_cells(const unsigned int part) const;

    /** The number of unknowns of the undecomposed body without prescribed DoFs. Collective. */
    unsigned int
    n_free_dofs() const;

    /** Whether the mesh holds only the cells of this rank's parts. */
    bool
    distributed() const
    {
      return cells_distributed;
    }

    /**
     * The communicator over which the body's cells are distributed: that of
     * create_and_partition() if they are, else MPI_COMM_SELF (the mesh is whole).
     */
    MPI_Comm
    mesh_comm() const
    {
      return distributed() ? comm : MPI_COMM_SELF;
    }

    /** The number in the whole mesh of vertex @p v of this rank's mesh. */
    unsigned int
    body_vertex(const unsigned int v) const
    {
      return vertex_number.empty() ? v : vertex_number[v];
    }

    /** The active cell index in the whole mesh of active cell @p c of this rank's mesh. */
    unsigned int
    body_cell(const unsigned int c) const
    {
      return cell_number.empty() ? c : cell_number[c];
    }

    /**
     * For every vertex of this rank's mesh, the parts whose cells contain it, in increasing
     * order (parts_of_vertices() of the whole mesh).
     */
    std::vector<std::vector<unsigned int>>
    parts_of_mesh_vertices() const;

    /**
     * The vertices of this rank's mesh that it reports, in increasing order: those whose
     * lowest-numbered part it holds (every used vertex of a whole mesh), so that every vertex of
     * the body is reported by one rank.
     */
    std::vector<unsigned int>
    reported_vertices() const;

    /**
     * The rank of mesh_comm() that holds the cells of part @p part (0, this rank, if the mesh is
     * whole).
     */
    unsigned int
    rank_of_part(const unsigned int part) const
    {
      return distributed() ? part_owner[part] : 0;
    }

    /** Whether this rank holds the cells of part @p part. */
    bool
    holds_part(const unsigned int part) const
    {
      return !distributed() || !cells_of_part[part].empty();
    }

    Parameters::Body         parameters;
    unsigned int             index;
    dealii::Triangulation<3> mesh;
    /** Γ_u by body vertex: of the vertices of this rank's mesh. */
    std::map<unsigned int, Prescribed> prescribed;
    /** The part of every active cell of this rank's mesh, and the number of parts. */
    CellPartition partition;
    /** The number of cells of every part (all parts). */
    std::vector<unsigned int> cells_per_part;
    /** The numbers of cells and of (used) vertices of the whole body. */
    unsigned int n_cells = 0, n_vertices = 0;
    /**
     * The active cells of every part of @p partition, in the order of the active cells. Listed
     * once, so that building a subdomain visits its own cells only (not every cell of the body
     * once per subdomain, which is quadratic in the number of subdomains).
     */
    std::vector<std::vector<dealii::Triangulation<3>::active_cell_iterator>> cells_of_part;

  private:
    /** Lists cells_of_part. */
    void
    list_cells_of_parts();

    /** Makes this rank's mesh of the cells of its parts @p own (distributed). */
    void
    hold(const std::vector<PartCells> &own);

    /** Γ_u from the boundary faces of this rank's mesh, made consistent over the ranks. */
    void
    collect_prescribed();

    MPI_Comm comm              = MPI_COMM_SELF;
    bool     cells_distributed = false;
    /** Distributed, for a box cut into blocks of cubes: every rank makes its own parts. */
    std::optional<LatticeParts> lattice;
    /** Distributed: the body's numbers of the vertices and cells of this rank's mesh. */
    std::vector<unsigned int> vertex_number, cell_number;
    /** Distributed: the rank that owns every part. */
    std::vector<unsigned int> part_owner;
    /** Distributed: the parts that hold every vertex of this rank's mesh (CSR). */
    std::vector<unsigned int> holder_start, holder_parts;
  };
} // namespace FetiContact
