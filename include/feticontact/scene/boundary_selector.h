#pragma once

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/types.h>
#include <deal.II/grid/tria.h>

#include <feticontact/scene/mesh_transform.h>

#include <mpi.h>
#include <string>

namespace FetiContact
{
  /**
   * Boundary id that marks, in the mesh of a subdomain, the faces shared with another subdomain
   * of the same body (the FETI interface). Meshes given by the user must not use it.
   */
  constexpr dealii::types::boundary_id interface_boundary_id = 254;

  /**
   * A part of a body's boundary as named in a parameter file. Either a boundary id of the mesh
   * (a Gmsh physical tag, or 0…5 for the faces x = xmin, x = xmax, y = ymin, …, z = zmax of a
   * generated box), or a plane `x = value` (also `y`, `z`; the value may be `xmin`, `xmax`,
   * … for the bounding box of the body) that selects every boundary face lying in it. Planes
   * are in the body's own frame: a body moved by its Mesh/Transform is selected as before the
   * move.
   */
  class BoundarySelector
  {
  public:
    /** Parses the text; @p what names the parameter for error messages. */
    static BoundarySelector
    parse(const std::string &text, const std::string &what);

    /**
     * Fixes the numeric value of `xmin`-like planes from the body's bounding box and checks
     * that the selector names a part of the body's boundary (an existing boundary id, or a plane
     * that contains at least one boundary face). @p mesh holds this rank's cells of the body and
     * @p comm the ranks that hold the others (MPI_COMM_SELF for a whole mesh); faces with
     * interface_boundary_id are not on the body's boundary. @p frame is the transform of the
     * body's mesh: planes are tested on the vertices taken back to the body's own frame. Throws
     * with a message naming the selector on every rank. Collective.
     */
    void
    resolve(const dealii::Triangulation<3>  &mesh,
            const std::string               &body_name,
            const MPI_Comm                   comm  = MPI_COMM_SELF,
            const Parameters::MeshTransform &frame = {});

    /** Whether the boundary face @p face belongs to this part of the boundary. */
    bool
    contains(const dealii::TriaAccessor<2, 3, 3> &face) const;

    /** The selector as the user wrote it. */
    const std::string &
    name() const
    {
      return text;
    }

  private:
    enum class Kind
    {
      boundary_id,
      plane
    };
    Kind                       kind = Kind::boundary_id;
    dealii::types::boundary_id id   = 0;
    unsigned int               axis = 0;
    /** -1: the bounding box minimum, +1: its maximum, 0: the number in value. */
    int         bound     = 0;
    double      value     = 0;
    double      tolerance = 0;
    std::string text;
    /** The transform of the body's mesh (resolve()). */
    Parameters::MeshTransform frame;
  };
} // namespace FetiContact
