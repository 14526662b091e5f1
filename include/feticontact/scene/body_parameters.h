#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <feticontact/scene/boundary_selector.h>
#include <feticontact/scene/mesh_transform.h>
#include <feticontact/scene/parameter_file.h>

#include <array>
#include <optional>
#include <string>
#include <vector>

/**
 * The description of one elastic body in the parameter file: its mesh, its material, its
 * boundary conditions and its decomposition into FETI subdomains. Each class is one
 * subsection of `subsection Body N`.
 */
namespace FetiContact::Parameters
{
  /** `subsection Mesh`: where the tetrahedral mesh of the body comes from. */
  struct Mesh
  {
    enum class Type
    {
      box,
      gmsh
    };
    Type type = Type::box;

    /** Generated box: corners (m) and the number of cubes along x, y, z. */
    dealii::Point<3>            lower_corner;
    dealii::Point<3>            upper_corner;
    std::array<unsigned int, 3> subdivisions{{1, 1, 1}};
    /** Tetrahedra per cube of the generated box: 5 or 6 (Kuhn split around the main diagonal). */
    unsigned int tetrahedra_per_cube = 6;
    /** Box: β ≥ 0, cubes shrink towards the focus (see MeshGeneration::grade_and_bend). */
    double grading = 0;
    /** Box: R > 0 bends the face z = zmin into a sphere of radius R; 0: flat. */
    double spherical_bottom_radius = 0;
    /**
     * Box: the point (x_f, y_f, zmin) of the bottom face the grading shrinks towards and the
     * spherical bottom touches the plane z = zmin at; the lower corner unless given.
     */
    dealii::Point<3> focus;

    /**
     * Gmsh file (`.msh`); boundary ids are the physical tags of its triangles. A relative path is
     * taken from the folder of the parameter file that names it.
     */
    std::string file;

    /** The rigid motion from the body's own frame (the above) to the scene. */
    MeshTransform transform;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    /** Reads `subsection Mesh`; @p origins are those of the body's subsection. */
    void
    parse_parameters(dealii::ParameterHandler &prm, const EntryOrigins &origins);
  };

  /** `subsection Material`: isotropic linear elasticity. */
  struct Material
  {
    double youngs_modulus = 1.0;
    double poissons_ratio = 0.3;

    /** The Lamé constants. */
    double
    lambda() const
    {
      return youngs_modulus * poissons_ratio / ((1 + poissons_ratio) * (1 - 2 * poissons_ratio));
    }
    double
    mu() const
    {
      return youngs_modulus / (2 * (1 + poissons_ratio));
    }

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /** A displacement prescribed on a part of the boundary, component by component. */
  struct PrescribedDisplacement
  {
    BoundarySelector                     boundary;
    std::array<std::optional<double>, 3> value;
  };

  /** A surface traction (Pa) on a part of the boundary. */
  struct Traction
  {
    BoundarySelector     boundary;
    dealii::Tensor<1, 3> value;
  };

  /** `subsection Boundary conditions`: Γ_u and Γ_t, and the volume force. */
  struct BoundaryConditions
  {
    std::vector<PrescribedDisplacement> prescribed_displacements;
    std::vector<Traction>               tractions;
    dealii::Tensor<1, 3>                volume_force;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /** `subsection Decomposition`: how the body is split into FETI subdomains. */
  struct Decomposition
  {
    enum class Method
    {
      automatic, ///< subdomains of about automatic_subdomain_unknowns unknowns
      blocks,    ///< equal boxes of the bounding box
      metis      ///< METIS with a given number of parts
    };
    Method method = Method::automatic;
    /** Structured blocks of the bounding box along x, y, z (cells go by their centroid). */
    std::array<unsigned int, 3> blocks{{1, 1, 1}};
    /** METIS: the number of parts. */
    unsigned int n_parts = 1;
    /**
     * The size of the subdomains of Method::automatic, in unknowns of the subdomain (3 per
     * vertex, its copies of the interface vertices included): on a generated box, cubes of
     * 6 × 6 × 6 cells. The cost of a contact solve is about n_A × the cost of one multiplication
     * by F plus the QP bookkeeping and the factorization: larger subdomains make the local solves
     * dearer per unknown, smaller ones make the dual and the coarse problem larger and n_A grow.
     * On the brick (μ = 0.1 and 0.3, k = 8, 16, 24; benchmarks/subdomain_size.py) cubes of 6
     * cells gave the shortest solves, cubes of 4 and 8 cells up to 1.1–1.8 times longer ones;
     * METIS parts of the same size needed 2–4 times as many multiplications as the cubes.
     */
    static constexpr unsigned int automatic_subdomain_unknowns = 1000;
    /**
     * Method::automatic on a generated box of @p subdivisions cubes: the number of blocks of
     * cubes along x, y, z. Their number is the box's volume over that of a cube holding
     * automatic_subdomain_unknowns unknowns; an axis with fewer cells than that cube's edge
     * keeps one block, and the blocks go to the other axes (a thin plate is cut across its
     * plane, not into slabs).
     */
    static std::array<unsigned int, 3>
    automatic_blocks(const std::array<unsigned int, 3> &subdivisions);
    /**
     * The number of parts that the method asks for on a body with the mesh @p mesh of
     * @p n_vertices vertices (before fragments are merged and before it is capped by the number
     * of cells).
     */
    unsigned int
    n_parts_for(const Mesh &mesh, const double n_vertices) const;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /** `subsection Body N`: one elastic body. */
  struct Body
  {
    std::string        name;
    Mesh               mesh;
    Material           material;
    BoundaryConditions boundary_conditions;
    Decomposition      decomposition;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    /** Reads the body's subsection; @p origins are those of that subsection. */
    void
    parse_parameters(dealii::ParameterHandler &prm, const EntryOrigins &origins);
  };
} // namespace FetiContact::Parameters
