#pragma once

#include <deal.II/grid/tria.h>

#include <feticontact/scene/body_parameters.h>

namespace FetiContact::MeshGeneration
{
  /**
   * Creates the tetrahedral mesh of a body as its `subsection Mesh` describes: a generated box
   * (boundary ids 0…5 on x = xmin, x = xmax, y = ymin, y = ymax, z = zmin, z = zmax) or a Gmsh
   * file. Checks that the mesh is not empty, holds tetrahedra only, has no inverted cell, and
   * does not use the reserved interface id. Throws InputError naming the cause.
   */
  void
  create_mesh(const Parameters::Mesh   &parameters,
              dealii::Triangulation<3> &mesh,
              const std::string        &body_name);

  /**
   * The box [p1, p2] with n[0] × n[1] × n[2] cubes, each split into six tetrahedra around its
   * diagonal from the lowest to the highest corner (all cubes split alike).
   */
  void
  subdivided_box_kuhn(dealii::Triangulation<3>          &mesh,
                      const std::array<unsigned int, 3> &n,
                      const dealii::Point<3>            &p1,
                      const dealii::Point<3>            &p2);

  /** The sum of the cells' volumes (GridTools::volume is wrong on tetrahedra in deal.II 9.4). */
  double
  volume(const dealii::Triangulation<3> &mesh);
} // namespace FetiContact::MeshGeneration
