#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/scene/mesh_generation.h>
#include <feticontact/scene/parameter_file.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace FetiContact::MeshGeneration
{
  using namespace dealii;

  namespace
  {
    double
    signed_volume(const std::array<Point<3>, 4> &p)
    {
      const Tensor<1, 3> a = p[1] - p[0], b = p[2] - p[0], c = p[3] - p[0];
      return (a * cross_product_3d(b, c)) / 6.0;
    }

    /**
     * A more precise cause for a Gmsh file that deal.II could not read, from its node list:
     * "node line N: <text> is not a finite coordinate", "the file ends inside its node list",
     * "its $Nodes header announces N nodes, but the node list has M lines" (MSH 2), or an empty
     * string when the node list looks sound (the cause is elsewhere).
     */
    std::string
    diagnose_gmsh_nodes(const std::string &file)
    {
      std::ifstream in(file);
      std::string   line;
      while (std::getline(in, line) && InputParsing::trim(line) != "$Nodes")
        ;
      if (!in)
        return "";
      unsigned int line_number = 0;
      double       announced   = -1; // the node count of an MSH 2 header
      while (std::getline(in, line))
        {
          const std::string trimmed = InputParsing::trim(line);
          if (trimmed == "$EndNodes")
            {
              if (announced >= 0 && announced != line_number - 1)
                return "its $Nodes header announces " + InputParsing::number_text(announced) +
                       " nodes, but the node list has " + std::to_string(line_number - 1) +
                       " lines";
              return "";
            }
          ++line_number;
          if (line_number == 1)
            {
              std::istringstream header(trimmed);
              double             count = 0, more = 0;
              if (header >> count && !(header >> more))
                announced = count;
            }
          std::istringstream words(trimmed);
          std::string        word;
          // The first line is the node count (MSH 2) or a block header (MSH 4): integers.
          while (words >> word)
            {
              char        *end   = nullptr;
              const double value = std::strtod(word.c_str(), &end);
              if (*end != '\0' || !std::isfinite(value))
                return "line " + std::to_string(line_number) + " of its node list: <" + word +
                       "> is not a finite number";
            }
        }
      return "the file ends inside its node list ($EndNodes is missing)";
    }

    /** The name of a Gmsh element type that is not a linear simplex or point, else "". */
    std::string
    unsupported_gmsh_element(const int type)
    {
      switch (type)
        {
          case 1:
          case 2:
          case 4:
          case 15:
            return "";
          case 3:
            return "4-node quadrangles";
          case 5:
            return "8-node hexahedra";
          case 6:
            return "6-node prisms";
          case 7:
            return "5-node pyramids";
          case 8:
            return "second-order (3-node) lines";
          case 9:
            return "second-order (6-node) triangles";
          case 10:
            return "second-order (9-node) quadrangles";
          case 11:
            return "second-order (10-node) tetrahedra";
          case 12:
            return "second-order (27-node) hexahedra";
          case 16:
            return "second-order (8-node) quadrangles";
          case 17:
            return "second-order (20-node) hexahedra";
          default:
            return "elements of Gmsh type " + std::to_string(type) +
                   " (higher order or other shapes)";
        }
    }

    /**
     * The element types of an ASCII Gmsh file (MSH 2 or 4) that are not linear simplices: the
     * first one found, described, or "" if all are linear tetrahedra, triangles, lines, points.
     */
    std::string
    diagnose_gmsh_elements(const std::string &file)
    {
      std::ifstream in(file);
      std::string   line;
      double        version = 0;
      while (std::getline(in, line))
        {
          const std::string trimmed = InputParsing::trim(line);
          if (trimmed == "$MeshFormat" && std::getline(in, line))
            version = std::atof(line.c_str());
          if (trimmed == "$Elements")
            break;
        }
      if (!in)
        return "";
      std::getline(in, line);
      if (version >= 4)
        {
          // Header: blocks, elements, min tag, max tag; per block: dim, tag, type, count.
          std::istringstream header(line);
          long               n_blocks = 0;
          header >> n_blocks;
          for (long b = 0; b < n_blocks && std::getline(in, line); ++b)
            {
              std::istringstream block(line);
              int                dim = 0, tag = 0, type = 0;
              long               count = 0;
              block >> dim >> tag >> type >> count;
              if (!unsupported_gmsh_element(type).empty())
                return unsupported_gmsh_element(type) + " (Gmsh element type " +
                       std::to_string(type) + ")";
              for (long e = 0; e < count && std::getline(in, line); ++e)
                ;
            }
          return "";
        }
      while (std::getline(in, line) && InputParsing::trim(line) != "$EndElements")
        {
          std::istringstream words(line);
          long               number = 0;
          int                type   = 0;
          if (words >> number >> type && !unsupported_gmsh_element(type).empty())
            return unsupported_gmsh_element(type) + " (Gmsh element type " + std::to_string(type) +
                   ")";
        }
      return "";
    }

    /**
     * Refuses a Gmsh file that deal.II cannot read as text: a folder, a binary file (file-type 1
     * in $MeshFormat), a byte-order mark, UTF-16, NUL bytes.
     */
    void
    check_gmsh_file(const std::string &file, const std::string &where)
    {
      require(!std::filesystem::is_directory(file),
              where + "the mesh file <" + file + "> is a folder, not a file.");
      std::ifstream in(file, std::ios::binary);
      std::string   first, format;
      std::getline(in, first);
      std::getline(in, format);
      if (InputParsing::trim(first) == "$MeshFormat")
        {
          std::istringstream words(format);
          std::string        version;
          int                file_type = 0;
          words >> version >> file_type;
          require(file_type != 1,
                  where + "the mesh file <" + file + "> is a binary Gmsh file (MSH " + version +
                    ", file-type 1 in $MeshFormat); deal.II reads ASCII Gmsh files only: save it "
                    "as ASCII (Gmsh: File > Export with 'Binary' unchecked, or the option "
                    "Mesh.Binary = 0).");
        }
      try
        {
          Parameters::check_text_file(file, "mesh file");
        }
      catch (const InputError &e)
        {
          throw InputError(where + e.what());
        }
    }

    /**
     * Checks the vertices of a mesh: coordinates within a range that double precision resolves
     * at the size of the cells, and no two distinct vertices at the same point (the two sides
     * of an internal crack, or nodes a mesher duplicated, which no cell shares).
     */
    void
    check_vertices(const Triangulation<3> &mesh, const std::string &where)
    {
      const auto &vertices = mesh.get_vertices();
      const auto &used     = mesh.get_used_vertices();
      // Beyond 1e15 in any unit the cells of a mesh one can store are below the rounding of
      // their coordinates.
      const double limit = 1e15;
      Point<3>     lower, upper;
      bool         first = true;
      for (unsigned int v = 0; v < vertices.size(); ++v)
        if (used[v])
          {
            for (unsigned int d = 0; d < 3; ++d)
              if (!(std::abs(vertices[v][d]) <= limit))
                throw InputError(where + "the mesh has a node at (" +
                                 InputParsing::number_text(vertices[v][0]) + ", " +
                                 InputParsing::number_text(vertices[v][1]) + ", " +
                                 InputParsing::number_text(vertices[v][2]) +
                                 "): coordinates beyond ±1e15 are not a mesh (a stray node, or "
                                 "a unit mixed up?).");
            for (unsigned int d = 0; d < 3; ++d)
              {
                lower[d] = first ? vertices[v][d] : std::min(lower[d], vertices[v][d]);
                upper[d] = first ? vertices[v][d] : std::max(upper[d], vertices[v][d]);
              }
            first = false;
          }
      const double diameter = lower.distance(upper);
      const double h_min    = GridTools::minimal_cell_diameter(mesh);
      require(diameter <= 1e9 * h_min,
              where + "the mesh extends over " + InputParsing::number_text(diameter) +
                " but its smallest cell measures " + InputParsing::number_text(h_min) +
                ": a ratio above 1e9 leaves the cells to rounding (a stray node far from the "
                "others?).");

      // A flat mesh (a box of no thickness) would pass for coincident vertices below.
      for (unsigned int d = 0; d < 3; ++d)
        require(upper[d] - lower[d] > 1e-9 * diameter,
                where + "the mesh is flat: it extends over " +
                  InputParsing::number_text(upper[d] - lower[d]) + " along " +
                  std::string(1, char('x' + d)) + " against " +
                  InputParsing::number_text(diameter) +
                  " in all (a body needs a thickness; a corner given twice?).");

      // Coincident vertices: equal after rounding to 1e-12 of the mesh's size, sorted.
      const double quantum = 1e-12 * diameter;
      using Key            = std::array<long long, 3>;
      std::vector<std::pair<Key, unsigned int>> keys;
      for (unsigned int v = 0; v < vertices.size(); ++v)
        if (used[v])
          {
            Key k;
            for (unsigned int d = 0; d < 3; ++d)
              k[d] = std::llround((vertices[v][d] - lower[d]) / quantum);
            keys.emplace_back(k, v);
          }
      std::sort(keys.begin(), keys.end());
      for (std::size_t i = 1; i < keys.size(); ++i)
        if (keys[i].first == keys[i - 1].first)
          {
            const Point<3> &x = vertices[keys[i].second];
            throw InputError(
              where + "the mesh has two distinct nodes at (" + InputParsing::number_text(x[0]) +
              ", " + InputParsing::number_text(x[1]) + ", " + InputParsing::number_text(x[2]) +
              ") (vertices " + std::to_string(keys[i - 1].second) + " and " +
              std::to_string(keys[i].second) +
              ") that no cell shares: an internal crack or duplicated nodes, which the bodies "
              "here cannot have (merge them, e.g. Gmsh's Coherence; a crack is two bodies in "
              "contact).");
          }
    }

    /** Boundary ids 0…5 by the face of the bounding box a boundary face lies in. */
    void
    colorize_box_faces(Triangulation<3> &mesh, const Point<3> &p1, const Point<3> &p2)
    {
      const double tol = 1e-10 * p1.distance(p2);
      for (const auto &cell : mesh.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              const Point<3> c = face->center();
              for (unsigned int d = 0; d < 3; ++d)
                {
                  if (std::abs(c[d] - p1[d]) < tol)
                    face->set_boundary_id(2 * d);
                  else if (std::abs(c[d] - p2[d]) < tol)
                    face->set_boundary_id(2 * d + 1);
                }
            }
    }
  } // namespace

  Point<3>
  kuhn_lattice_point(const std::array<unsigned int, 3> &n,
                     const Point<3>                    &p1,
                     const Point<3>                    &p2,
                     const std::array<unsigned int, 3> &i)
  {
    return Point<3>(p1[0] + (p2[0] - p1[0]) * i[0] / n[0],
                    p1[1] + (p2[1] - p1[1]) * i[1] / n[1],
                    p1[2] + (p2[2] - p1[2]) * i[2] / n[2]);
  }

  std::array<std::array<unsigned int, 3>, 4>
  kuhn_tetrahedron(const std::array<unsigned int, 3> &n,
                   const Point<3>                    &p1,
                   const Point<3>                    &p2,
                   const std::array<unsigned int, 3> &cube,
                   const unsigned int                 t)
  {
    // The six monotone lattice paths from corner 0 to corner 7 of the unit cube, one per
    // ordering of the axes; corner c has offsets (c & 1, (c >> 1) & 1, (c >> 2) & 1).
    static const unsigned int paths[6][4] = {
      {0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
    std::array<std::array<unsigned int, 3>, 4> vertex;
    std::array<Point<3>, 4>                    p;
    for (unsigned int v = 0; v < 4; ++v)
      {
        const unsigned int c = paths[t][v];
        vertex[v] = {{cube[0] + (c & 1), cube[1] + ((c >> 1) & 1), cube[2] + ((c >> 2) & 1)}};
        p[v]      = kuhn_lattice_point(n, p1, p2, vertex[v]);
      }
    if (signed_volume(p) < 0)
      std::swap(vertex[1], vertex[2]);
    return vertex;
  }

  void
  subdivided_box_kuhn(Triangulation<3>                  &mesh,
                      const std::array<unsigned int, 3> &n,
                      const Point<3>                    &p1,
                      const Point<3>                    &p2)
  {
    std::vector<Point<3>> vertices;
    vertices.reserve((n[0] + 1) * (n[1] + 1) * (n[2] + 1));
    for (unsigned int k = 0; k <= n[2]; ++k)
      for (unsigned int j = 0; j <= n[1]; ++j)
        for (unsigned int i = 0; i <= n[0]; ++i)
          vertices.push_back(kuhn_lattice_point(n, p1, p2, {{i, j, k}}));
    std::vector<CellData<3>> cells;
    cells.reserve(6 * n[0] * n[1] * n[2]);
    for (unsigned int k = 0; k < n[2]; ++k)
      for (unsigned int j = 0; j < n[1]; ++j)
        for (unsigned int i = 0; i < n[0]; ++i)
          for (unsigned int t = 0; t < 6; ++t)
            {
              CellData<3> cell(4);
              const auto  vertex = kuhn_tetrahedron(n, p1, p2, {{i, j, k}}, t);
              for (unsigned int v = 0; v < 4; ++v)
                cell.vertices[v] =
                  vertex[v][0] + (n[0] + 1) * (vertex[v][1] + (n[1] + 1) * vertex[v][2]);
              cells.push_back(cell);
            }
    mesh.create_triangulation(vertices, cells, SubCellData());
    colorize_box_faces(mesh, p1, p2);
  }

  Point<3>
  graded_point(const Point<3> &x,
               const Point<3> &p1,
               const Point<3> &p2,
               const Point<3> &focus,
               const double    grading,
               const double    spherical_bottom_radius)
  {
    const double beta = grading, R = spherical_bottom_radius;
    if (beta == 0 && R == 0)
      return x;
    // The distance from the focus to the face on the side of x_d (0 when the focus lies on it).
    const auto side = [&](const unsigned int d, const double x_d) {
      return x_d >= focus[d] ? p2[d] - focus[d] : focus[d] - p1[d];
    };
    Point<3> xi;
    double   rho = 0;
    for (unsigned int d = 0; d < 3; ++d)
      {
        const double length = side(d, x[d]);
        xi[d]               = length > 0 ? (x[d] - focus[d]) / length : 0.;
        rho                 = std::max(rho, std::abs(xi[d]));
      }
    // g(ρ)/ρ with g(ρ) = (e^{βρ} − 1)/(e^β − 1); its limit β/(e^β − 1) at ρ = 0.
    const double scale = beta == 0 ? 1. :
                                     (rho > 0 ? std::expm1(beta * rho) / std::expm1(beta) / rho :
                                                beta / std::expm1(beta));
    Point<3>     y;
    for (unsigned int d = 0; d < 3; ++d)
      y[d] = focus[d] + scale * xi[d] * side(d, x[d]);
    if (R > 0)
      {
        const double r2 =
          (y[0] - focus[0]) * (y[0] - focus[0]) + (y[1] - focus[1]) * (y[1] - focus[1]);
        const double zeta = (y[2] - p1[2]) / (p2[2] - p1[2]);
        y[2] += (1 - zeta) * (R - std::sqrt(R * R - r2));
      }
    return y;
  }

  void
  grade_and_bend(Triangulation<3> &mesh,
                 const Point<3>   &p1,
                 const Point<3>   &p2,
                 const Point<3>   &focus,
                 const double      grading,
                 const double      spherical_bottom_radius)
  {
    if (grading == 0 && spherical_bottom_radius == 0)
      return;
    GridTools::transform(
      [&](const Point<3> &x) {
        return graded_point(x, p1, p2, focus, grading, spherical_bottom_radius);
      },
      mesh);
  }

  double
  volume(const Triangulation<3> &mesh)
  {
    double v = 0;
    for (const auto &cell : mesh.active_cell_iterators())
      v += cell->measure();
    return v;
  }

  void
  create_mesh(const Parameters::Mesh &parameters,
              Triangulation<3>       &mesh,
              const std::string      &body_name)
  {
    const std::string where = "Body '" + body_name + "': ";
    if (parameters.type == Parameters::Mesh::Type::box)
      {
        if (parameters.tetrahedra_per_cube == 6)
          subdivided_box_kuhn(mesh,
                              parameters.subdivisions,
                              parameters.lower_corner,
                              parameters.upper_corner);
        else
          {
            const std::vector<unsigned int> reps(parameters.subdivisions.begin(),
                                                 parameters.subdivisions.end());
            GridGenerator::subdivided_hyper_rectangle_with_simplices(mesh,
                                                                     reps,
                                                                     parameters.lower_corner,
                                                                     parameters.upper_corner);
            colorize_box_faces(mesh, parameters.lower_corner, parameters.upper_corner);
          }
        grade_and_bend(mesh,
                       parameters.lower_corner,
                       parameters.upper_corner,
                       parameters.focus,
                       parameters.grading,
                       parameters.spherical_bottom_radius);
      }
    else
      {
        check_gmsh_file(parameters.file, where);
        std::ifstream in(parameters.file);
        require(static_cast<bool>(in),
                where + "cannot open the mesh file <" + parameters.file + ">.");
        require(in.peek() != std::ifstream::traits_type::eof(),
                where + "the mesh file <" + parameters.file + "> is empty.");
        GridIn<3> grid_in;
        grid_in.attach_triangulation(mesh);
        try
          {
            grid_in.read_msh(in);
          }
        catch (const std::exception &e)
          {
            std::string msg = e.what();
            const auto  pos = msg.find("Additional information:");
            if (pos != std::string::npos)
              msg = InputParsing::trim(msg.substr(pos + 23, msg.find("Stacktrace") - pos - 23));
            std::string cause = diagnose_gmsh_elements(parameters.file);
            if (!cause.empty())
              throw InputError(where + "the Gmsh file <" + parameters.file + "> has " + cause +
                               ": only linear 4-node tetrahedra (with 3-node triangles on the "
                               "boundary) are supported; mesh with Mesh.ElementOrder = 1.");
            cause = diagnose_gmsh_nodes(parameters.file);
            throw InputError(where + "cannot read the Gmsh file <" + parameters.file +
                             ">: " + (cause.empty() ? msg : cause + " (deal.II: " + msg + ")"));
          }
      }

    require(mesh.n_active_cells() > 0, where + "the mesh has no cells.");
    check_vertices(mesh, where);
    // The messages are built only when a check fails: this loop visits every cell of the body
    // (two million at 10⁶ unknowns), on every MPI rank.
    for (const auto &cell : mesh.active_cell_iterators())
      {
        if (cell->reference_cell() != ReferenceCells::Tetrahedron)
          throw InputError(where + "the mesh has a cell that is not a tetrahedron (only linear "
                                   "4-node tetrahedra are supported).");
        std::array<Point<3>, 4> p;
        for (unsigned int v = 0; v < 4; ++v)
          p[v] = cell->vertex(v);
        const double h = p[0].distance(p[1]);
        if (!(signed_volume(p) > 1e-12 * h * h * h))
          throw InputError(where + "the mesh has a degenerate or inverted tetrahedron at " +
                           InputParsing::number_text(cell->center()[0]) + ", " +
                           InputParsing::number_text(cell->center()[1]) + ", " +
                           InputParsing::number_text(cell->center()[2]) + ".");
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() == interface_boundary_id)
            throw InputError(where + "boundary id " + std::to_string(interface_boundary_id) +
                             " is reserved for subdomain interfaces.");
      }
  }
} // namespace FetiContact::MeshGeneration
