#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/scene/mesh_generation.h>

#include <cmath>
#include <cstdlib>
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
     * "node line N: <text> is not a finite coordinate", "the file ends inside its node list", or
     * an empty string when the node list looks sound (the cause is elsewhere).
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
      while (std::getline(in, line))
        {
          const std::string trimmed = InputParsing::trim(line);
          if (trimmed == "$EndNodes")
            return "";
          ++line_number;
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
          vertices.emplace_back(p1[0] + (p2[0] - p1[0]) * i / n[0],
                                p1[1] + (p2[1] - p1[1]) * j / n[1],
                                p1[2] + (p2[2] - p1[2]) * k / n[2]);
    const auto index = [&](unsigned int i, unsigned int j, unsigned int k) {
      return i + (n[0] + 1) * (j + (n[1] + 1) * k);
    };

    // The six monotone lattice paths from corner 0 to corner 7 of the unit cube, one per
    // ordering of the axes; corner c has offsets (c & 1, (c >> 1) & 1, (c >> 2) & 1).
    const unsigned int paths[6][4] = {
      {0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

    std::vector<CellData<3>> cells;
    cells.reserve(6 * n[0] * n[1] * n[2]);
    for (unsigned int k = 0; k < n[2]; ++k)
      for (unsigned int j = 0; j < n[1]; ++j)
        for (unsigned int i = 0; i < n[0]; ++i)
          for (const auto &path : paths)
            {
              CellData<3>             cell(4);
              std::array<Point<3>, 4> p;
              for (unsigned int v = 0; v < 4; ++v)
                {
                  const unsigned int c = path[v];
                  cell.vertices[v]     = index(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
                  p[v]                 = vertices[cell.vertices[v]];
                }
              if (signed_volume(p) < 0)
                std::swap(cell.vertices[1], cell.vertices[2]);
              cells.push_back(cell);
            }
    mesh.create_triangulation(vertices, cells, SubCellData());
    colorize_box_faces(mesh, p1, p2);
  }

  void
  grade_and_bend(Triangulation<3> &mesh,
                 const Point<3>   &p1,
                 const Point<3>   &p2,
                 const Point<3>   &focus,
                 const double      grading,
                 const double      spherical_bottom_radius)
  {
    const double beta = grading, R = spherical_bottom_radius;
    if (beta == 0 && R == 0)
      return;
    // The distance from the focus to the face on the side of x_d (0 when the focus lies on it).
    const auto side = [&](const unsigned int d, const double x) {
      return x >= focus[d] ? p2[d] - focus[d] : focus[d] - p1[d];
    };
    GridTools::transform(
      [&](const Point<3> &x) {
        Point<3> xi;
        double   rho = 0;
        for (unsigned int d = 0; d < 3; ++d)
          {
            const double length = side(d, x[d]);
            xi[d]               = length > 0 ? (x[d] - focus[d]) / length : 0.;
            rho                 = std::max(rho, std::abs(xi[d]));
          }
        // g(ρ)/ρ with g(ρ) = (e^{βρ} − 1)/(e^β − 1); its limit β/(e^β − 1) at ρ = 0.
        const double scale =
          beta == 0 ?
            1. :
            (rho > 0 ? std::expm1(beta * rho) / std::expm1(beta) / rho : beta / std::expm1(beta));
        Point<3> y;
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
            const std::string cause = diagnose_gmsh_nodes(parameters.file);
            throw InputError(where + "cannot read the Gmsh file <" + parameters.file +
                             ">: " + (cause.empty() ? msg : cause + " (deal.II: " + msg + ")"));
          }
      }

    require(mesh.n_active_cells() > 0, where + "the mesh has no cells.");
    // The messages are built only when a check fails: this loop visits every cell of the body
    // (two million at 10⁶ unknowns), on every MPI rank.
    for (const auto &cell : mesh.active_cell_iterators())
      {
        if (cell->reference_cell() != ReferenceCells::Tetrahedron)
          throw InputError(where + "the mesh has a cell that is not a tetrahedron (only linear "
                                   "tetrahedra are supported).");
        std::array<Point<3>, 4> p;
        for (unsigned int v = 0; v < 4; ++v)
          p[v] = cell->vertex(v);
        const double h = p[0].distance(p[1]);
        if (!(signed_volume(p) > 1e-12 * h * h * h))
          throw InputError(where + "the mesh has a degenerate or inverted tetrahedron at " +
                           std::to_string(cell->center()[0]) + ", " +
                           std::to_string(cell->center()[1]) + ", " +
                           std::to_string(cell->center()[2]) + ".");
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary() && face->boundary_id() == interface_boundary_id)
            throw InputError(where + "boundary id " + std::to_string(interface_boundary_id) +
                             " is reserved for subdomain interfaces.");
      }
  }
} // namespace FetiContact::MeshGeneration
