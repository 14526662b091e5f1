#pragma once

#include <deal.II/grid/tria.h>

#include <feticontact/scene/body_parameters.h>
#include <feticontact/scene/decomposition.h>

#include <array>
#include <map>
#include <optional>

namespace FetiContact
{
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
