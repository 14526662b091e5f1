#pragma once

#include <deal.II/grid/tria.h>

#include <feticontact/scene/body_parameters.h>

#include <array>

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
   * The point of lattice index @p i (per axis 0 … n_d) of the box from @p p1 to @p p2 in
   * @p n cubes, undistorted.
   */
  dealii::Point<3>
  kuhn_lattice_point(const std::array<unsigned int, 3> &n,
                     const dealii::Point<3>            &p1,
                     const dealii::Point<3>            &p2,
                     const std::array<unsigned int, 3> &i);

  /**
   * Tetrahedron @p t (0 … 5) of cube @p cube of that box, as subdivided_box_kuhn() makes it:
   * the lattice indices of its four vertices in the order of the cell's vertices.
   */
  std::array<std::array<unsigned int, 3>, 4>
  kuhn_tetrahedron(const std::array<unsigned int, 3> &n,
                   const dealii::Point<3>            &p1,
                   const dealii::Point<3>            &p2,
                   const std::array<unsigned int, 3> &cube,
                   const unsigned int                 t);

  /**
   * The box [p1, p2] with n[0] × n[1] × n[2] cubes, each split into six tetrahedra around its
   * diagonal from the lowest to the highest corner (all cubes split alike).
   */
  void
  subdivided_box_kuhn(dealii::Triangulation<3>          &mesh,
                      const std::array<unsigned int, 3> &n,
                      const dealii::Point<3>            &p1,
                      const dealii::Point<3>            &p2);

  /**
   * The point of the graded and bent box (grade_and_bend()) that the point @p x of the
   * undistorted box becomes.
   */
  dealii::Point<3>
  graded_point(const dealii::Point<3> &x,
               const dealii::Point<3> &p1,
               const dealii::Point<3> &p2,
               const dealii::Point<3> &focus,
               const double            grading,
               const double            spherical_bottom_radius);

  /**
   * Moves the vertices of the box [p1, p2] (its faces stay where they are) towards the focus
   * c ∈ [p1, p2] (c_z = z1): with ξ_d ∈ [−1, 1] the relative position of x_d between c_d and the
   * face on its side (ξ_d = (x_d − c_d)/(p2_d − c_d) above c_d, (x_d − c_d)/(c_d − p1_d) below)
   * and ρ = max_d |ξ_d|, ξ ← ξ g(ρ)/ρ with g(ρ) = (e^{βρ} − 1)/(e^β − 1) for the grading β > 0
   * (cells of β/(e^β − 1) times the uniform size near c, growing geometrically away from it,
   * each about as wide as deep), then, for R > 0, z ← z + (1 − ζ)(R − √(R² − (x − c_x)² −
   * (y − c_y)²)) with ζ the relative height: the face z = z1 becomes the sphere of radius R
   * touching the plane z = z1 at (c_x, c_y), the face z = z2 stays flat. With c = p1 (a corner)
   * a quarter of a spherical indenter, with c in the middle of an edge of the bottom face a half,
   * with c in its middle the whole indenter.
   */
  void
  grade_and_bend(dealii::Triangulation<3> &mesh,
                 const dealii::Point<3>   &p1,
                 const dealii::Point<3>   &p2,
                 const dealii::Point<3>   &focus,
                 const double              grading,
                 const double              spherical_bottom_radius);

  /** The sum of the cells' volumes (GridTools::volume is wrong on tetrahedra in deal.II 9.4). */
  double
  volume(const dealii::Triangulation<3> &mesh);
} // namespace FetiContact::MeshGeneration
