#include <feticontact/base/input_parsing.h>
#include <feticontact/scene/body_parameters.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace FetiContact::Parameters
{
  using namespace dealii;

  void
  Mesh::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Mesh");
    prm.declare_entry("Type",
                      "box",
                      Patterns::Selection("box|gmsh"),
                      "Where the tetrahedral mesh comes from: 'box' generates the box between "
                      "the two corners, each of its cubes split into tetrahedra; 'gmsh' reads "
                      "'File'.");
    prm.declare_entry("Lower corner",
                      "0, 0, 0",
                      Patterns::Anything(),
                      "Box: the corner with the smallest coordinates (m).");
    prm.declare_entry("Upper corner",
                      "1, 1, 1",
                      Patterns::Anything(),
                      "Box: the corner with the largest coordinates (m).");
    prm.declare_entry("Subdivisions",
                      "4, 4, 4",
                      Patterns::Anything(),
                      "Box: the number of cubes along x, y, z. Boundary ids of the box: "
                      "0 (x = xmin), 1 (x = xmax), 2 (y = ymin), 3 (y = ymax), 4 (z = zmin), "
                      "5 (z = zmax).");
    prm.declare_entry("Tetrahedra per cube",
                      "6",
                      Patterns::Selection("5|6"),
                      "Box: 6 splits each cube around its main diagonal (all cubes alike); "
                      "5 is deal.II's split with alternating orientation.");
    prm.declare_entry("Grading",
                      "0",
                      Patterns::Double(0, 50),
                      "Box: β ≥ 0 shrinks the cubes towards the focus (see 'Focus'; the lower "
                      "corner by default): with ξ ∈ [−1, 1]³ the relative position between the "
                      "focus and the faces and ρ = max_d |ξ_d|, a point moves to "
                      "ξ g(ρ)/ρ, g(ρ) = (e^{βρ} − 1)/(e^β − 1). Near the focus the cells are "
                      "β/(e^β − 1) times the uniform size and about equally shaped; away from it "
                      "they grow by about e^(β/n) per cell (n the subdivisions). The faces of the "
                      "box stay in place (boundary ids as without grading). 0: uniform.");
    prm.declare_entry("Spherical bottom radius",
                      "0",
                      Patterns::Double(0),
                      "Box: R > 0 bends the face z = zmin into the sphere of radius R that touches "
                      "the plane z = zmin at the focus (x_f, y_f), the symmetry axis of the body "
                      "being the line x = x_f, y = y_f (focus at the lower corner: a quarter of a "
                      "spherical indenter, with symmetry conditions on x = xmin and y = ymin; in "
                      "the middle of the edge y = ymin: a half, symmetric about y = ymin): a "
                      "point moves up by (1 − ζ)(R − √(R² − (x − x_f)² − (y − y_f)²)), "
                      "ζ = (z − zmin)/(zmax − zmin). Needs R − √(R² − r²) < (zmax − zmin)/2 with "
                      "r the largest distance from the focus to a corner of the bottom face. "
                      "Applied after the grading. 0: flat.");
    prm.declare_entry("Focus",
                      "",
                      Patterns::Anything(),
                      "Box: the point the grading shrinks towards, 'x, y' in the bottom face "
                      "z = zmin (where the spherical bottom touches the plane z = zmin) or "
                      "'x, y, z' anywhere in the box (on a face: a block refined towards a point "
                      "of its top). Empty: the lower corner.");
    prm.declare_entry("File",
                      "",
                      Patterns::Anything(),
                      "Gmsh: the mesh file (.msh, relative to the parameter file's folder). "
                      "Tetrahedra only; boundary ids are the physical tags of its triangles.");
    MeshTransform::declare_parameters(prm);
    prm.leave_subsection();
  }

  void
  Mesh::parse_parameters(ParameterHandler &prm, const EntryOrigins &origins)
  {
    prm.enter_subsection("Mesh");
    type = prm.get("Type") == "box" ? Type::box : Type::gmsh;
    if (type == Type::box)
      {
        lower_corner = InputParsing::parse_point(prm.get("Lower corner"), "Mesh/Lower corner");
        upper_corner = InputParsing::parse_point(prm.get("Upper corner"), "Mesh/Upper corner");
        for (unsigned int d = 0; d < 3; ++d)
          require(upper_corner[d] > lower_corner[d],
                  ("Mesh: 'Upper corner' must exceed 'Lower corner' in every "
                   "coordinate (coordinate " +
                   std::to_string(d) + ")."));
        const auto s =
          InputParsing::parse_positive_integers(prm.get("Subdivisions"), 3, "Mesh/Subdivisions");
        subdivisions                 = {{s[0], s[1], s[2]}};
        tetrahedra_per_cube          = prm.get_integer("Tetrahedra per cube");
        grading                      = prm.get_double("Grading");
        spherical_bottom_radius      = prm.get_double("Spherical bottom radius");
        focus                        = lower_corner;
        const std::string focus_text = InputParsing::trim(prm.get("Focus"));
        if (!focus_text.empty())
          {
            const unsigned int n_given = InputParsing::split(focus_text, ',').size() == 3 ? 3 : 2;
            const auto         xyz = InputParsing::parse_doubles(focus_text, n_given, "Mesh/Focus");
            for (unsigned int d = 0; d < n_given; ++d)
              {
                require(xyz[d] >= lower_corner[d] && xyz[d] <= upper_corner[d],
                        "Mesh/Focus: the point (" + focus_text +
                          ") must lie in the box (coordinate " + std::to_string(d) +
                          " outside [lower corner, upper corner]).");
                focus[d] = xyz[d];
              }
            require(spherical_bottom_radius == 0 || focus[2] == lower_corner[2],
                    "Mesh/Focus: with a Spherical bottom radius the focus must lie in the bottom "
                    "face (z = zmin), where the sphere touches.");
          }
        const double R  = spherical_bottom_radius;
        double       r2 = 0; // the largest squared distance from the focus to a bottom corner
        for (const double x : {lower_corner[0], upper_corner[0]})
          for (const double y : {lower_corner[1], upper_corner[1]})
            r2 = std::max(r2, (x - focus[0]) * (x - focus[0]) + (y - focus[1]) * (y - focus[1]));
        require(R == 0 || (r2 < R * R &&
                           R - std::sqrt(R * R - r2) < 0.5 * (upper_corner[2] - lower_corner[2])),
                "Mesh/Spherical bottom radius: the bent bottom must stay in the lower half of "
                "the box, R − √(R² − r²) < (zmax − zmin)/2 with r the largest distance from the "
                "focus to a corner of the bottom face (a larger radius or a smaller footprint).");
      }
    else
      {
        const std::string given = InputParsing::trim(prm.get("File"));
        require(!given.empty(), ("Mesh: 'Type = gmsh' needs 'File'."));
        file = origins.resolve("Mesh/File", given);
        std::error_code   error;
        const std::string tried =
          std::filesystem::absolute(file, error).lexically_normal().string();
        require(!std::filesystem::is_directory(file),
                "Mesh/File: <" + tried + "> is a folder, not a mesh file.");
        require(std::filesystem::is_regular_file(file),
                "Mesh/File: the mesh file <" + given + ">" + origins.where("Mesh/File") +
                  " does not exist: looked for <" + tried +
                  "> (a relative path is taken from the folder of the parameter file that "
                  "names it, from the working directory for a --set option or a parameter file "
                  "read from a pipe).");
      }
    transform.parse_parameters(prm);
    prm.leave_subsection();
  }

  void
  Material::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Material");
    prm.declare_entry("Young's modulus",
                      "2.12e11",
                      Patterns::Anything(),
                      "Young's modulus E (Pa), > 0.");
    prm.declare_entry("Poisson's ratio",
                      "0.277",
                      Patterns::Anything(),
                      "Poisson's ratio ν, in (-1, 0.5).");
    prm.leave_subsection();
  }

  void
  Material::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Material");
    youngs_modulus =
      InputParsing::parse_double(prm.get("Young's modulus"), "Material/Young's modulus");
    poissons_ratio =
      InputParsing::parse_double(prm.get("Poisson's ratio"), "Material/Poisson's ratio");
    require(youngs_modulus > 0,
            ("Material/Young's modulus must be positive; got " + prm.get("Young's modulus") + "."));
    require(poissons_ratio > -1 && poissons_ratio < 0.5,
            ("Material/Poisson's ratio must lie in (-1, 0.5); got " + prm.get("Poisson's ratio") +
             "."));
    prm.leave_subsection();
  }

  void
  BoundaryConditions::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Boundary conditions");
    prm.declare_entry("Clamped boundaries",
                      "",
                      Patterns::Anything(),
                      "Parts of the boundary with zero displacement, separated by ';'. A part "
                      "is a boundary id (a Gmsh physical tag; 0…5 for the faces of a box) or a "
                      "plane such as 'x = xmin' or 'z = 0.25'.");
    prm.declare_entry("Prescribed displacements",
                      "",
                      Patterns::Anything(),
                      "Displacements (m) prescribed component by component, entries separated "
                      "by ';', each 'part: ux, uy, uz' where a component may be 'free', e.g. "
                      "'x = xmax: 0.001, free, free'.");
    prm.declare_entry("Tractions",
                      "",
                      Patterns::Anything(),
                      "Surface tractions (Pa), entries separated by ';', each "
                      "'part: tx, ty, tz', e.g. 'z = zmax: 2e7, 0, -1e8'.");
    prm.declare_entry("Volume force",
                      "0, 0, 0",
                      Patterns::Anything(),
                      "Volume force density (N/m^3).");
    prm.leave_subsection();
  }

  namespace
  {
    /** Splits 'part: a, b, c' into the part and the values. */
    std::pair<BoundarySelector, std::vector<std::string>>
    parse_boundary_entry(const std::string &entry, const std::string &what)
    {
      const auto colon = entry.rfind(':');
      require(colon != std::string::npos,
              (what + ": <" + entry + "> should read 'part: value, value, value'."));
      const auto selector = BoundarySelector::parse(entry.substr(0, colon), what);
      const auto values   = InputParsing::split(entry.substr(colon + 1), ',');
      require(values.size() == 3, (what + ": <" + entry + "> needs three components."));
      return {selector, values};
    }
  } // namespace

  void
  BoundaryConditions::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Boundary conditions");
    prescribed_displacements.clear();
    tractions.clear();
    for (const auto &part : InputParsing::split(prm.get("Clamped boundaries"), ';'))
      {
        PrescribedDisplacement p;
        p.boundary = BoundarySelector::parse(part, "Boundary conditions/Clamped boundaries");
        p.value    = {{0.0, 0.0, 0.0}};
        prescribed_displacements.push_back(p);
      }
    for (const auto &entry : InputParsing::split(prm.get("Prescribed displacements"), ';'))
      {
        const std::string what  = "Boundary conditions/Prescribed displacements";
        auto [selector, values] = parse_boundary_entry(entry, what);
        PrescribedDisplacement p;
        p.boundary = selector;
        for (unsigned int d = 0; d < 3; ++d)
          if (values[d] != "free")
            p.value[d] = InputParsing::parse_double(values[d], what);
        prescribed_displacements.push_back(p);
      }
    for (const auto &entry : InputParsing::split(prm.get("Tractions"), ';'))
      {
        const std::string what  = "Boundary conditions/Tractions";
        auto [selector, values] = parse_boundary_entry(entry, what);
        Traction t;
        t.boundary = selector;
        for (unsigned int d = 0; d < 3; ++d)
          t.value[d] = InputParsing::parse_double(values[d], what);
        tractions.push_back(t);
      }
    volume_force =
      InputParsing::parse_vector(prm.get("Volume force"), "Boundary conditions/Volume force");
    prm.leave_subsection();
  }

  std::array<unsigned int, 3>
  Decomposition::automatic_blocks(const std::array<unsigned int, 3> &subdivisions)
  {
    // A cube of c × c × c cells holds about 3 (c + 1)³ unknowns: the target edge c, and the
    // number of parts of that volume.
    const double edge  = std::max(1.0, std::cbrt(automatic_subdomain_unknowns / 3.0) - 1);
    const double cells = double(subdivisions[0]) * subdivisions[1] * subdivisions[2];
    const double parts = std::max(1.0, cells / (edge * edge * edge));
    // Axes shorter than the block edge get one block; the parts go to the others, whose edge
    // is then the root of their cross-section per part (a thin plate is cut across its plane,
    // not into slabs).
    std::array<bool, 3> whole{{false, false, false}};
    double              free_edge = edge;
    for (unsigned int round = 0; round < 3; ++round)
      {
        double       free_cells = 1;
        unsigned int n_free     = 0;
        for (unsigned int d = 0; d < 3; ++d)
          if (!whole[d])
            {
              free_cells *= subdivisions[d];
              ++n_free;
            }
        if (n_free == 0)
          break;
        free_edge    = std::pow(free_cells / parts, 1.0 / n_free);
        bool changed = false;
        for (unsigned int d = 0; d < 3; ++d)
          if (!whole[d] && subdivisions[d] <= free_edge)
            whole[d] = changed = true;
        if (!changed)
          break;
      }
    std::array<unsigned int, 3> blocks;
    for (unsigned int d = 0; d < 3; ++d)
      blocks[d] =
        whole[d] ?
          1 :
          std::clamp<unsigned int>(std::lround(subdivisions[d] / free_edge), 1, subdivisions[d]);
    return blocks;
  }

  unsigned int
  Decomposition::n_parts_for(const Mesh &mesh, const double n_vertices) const
  {
    switch (method)
      {
        case Method::automatic:
          if (mesh.type == Mesh::Type::box)
            {
              const auto b = automatic_blocks(mesh.subdivisions);
              return b[0] * b[1] * b[2];
            }
          return static_cast<unsigned int>(
            std::max(1.0, std::round(3 * n_vertices / automatic_subdomain_unknowns)));
        case Method::blocks:
          return blocks[0] * blocks[1] * blocks[2];
        case Method::metis:
          return n_parts;
      }
    return 1;
  }

  void
  Decomposition::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Decomposition");
    prm.declare_entry("Method",
                      "automatic",
                      Patterns::Selection("automatic|blocks|metis"),
                      "How the body is split into FETI subdomains: 'automatic' makes subdomains "
                      "of about " +
                        std::to_string(automatic_subdomain_unknowns) +
                        " unknowns each (one for a smaller body): blocks of equally many cubes of "
                        "a generated box (graded or bent alike), METIS parts of a Gmsh mesh; "
                        "'blocks' cuts its "
                        "bounding box into 'Blocks' equal boxes (cells go by their centroid); "
                        "'metis' partitions the cells into 'Number of parts'. A part that the cut "
                        "leaves in pieces keeps its largest face-connected piece; the others join "
                        "the neighbouring part with which they share the most faces.");
    prm.declare_entry("Blocks",
                      "1, 1, 1",
                      Patterns::Anything(),
                      "blocks: the number of blocks along x, y, z.");
    prm.declare_entry("Number of parts", "1", Patterns::Integer(1), "metis: the number of parts.");
    prm.leave_subsection();
  }

  void
  Decomposition::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Decomposition");
    const std::string m = prm.get("Method");
    method = m == "automatic" ? Method::automatic : m == "blocks" ? Method::blocks : Method::metis;
    const auto b =
      InputParsing::parse_positive_integers(prm.get("Blocks"), 3, "Decomposition/Blocks");
    blocks  = {{b[0], b[1], b[2]}};
    n_parts = prm.get_integer("Number of parts");
    // The automatic method (the default) ignores both counts: one given without choosing the
    // method that uses it is a mistake, not a wish.
    require(method != Method::automatic || blocks == std::array<unsigned int, 3>{{1, 1, 1}},
            "Decomposition/Blocks = " + prm.get("Blocks") +
              " is not used by 'Method = automatic' (the default): set Method = blocks to cut "
              "the body into these blocks.");
    require(method != Method::automatic || n_parts == 1,
            "Decomposition/Number of parts = " + prm.get("Number of parts") +
              " is not used by 'Method = automatic' (the default): set Method = metis to "
              "partition the body into this many parts.");
    prm.leave_subsection();
  }

  void
  Body::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Name",
                      "",
                      Patterns::Anything(),
                      "A name for messages and output (default: 'body N').");
    Mesh::declare_parameters(prm);
    Material::declare_parameters(prm);
    BoundaryConditions::declare_parameters(prm);
    Decomposition::declare_parameters(prm);
  }

  void
  Body::parse_parameters(ParameterHandler &prm, const EntryOrigins &origins)
  {
    name = InputParsing::trim(prm.get("Name"));
    mesh.parse_parameters(prm, origins);
    material.parse_parameters(prm);
    boundary_conditions.parse_parameters(prm);
    decomposition.parse_parameters(prm);
  }
} // namespace FetiContact::Parameters
