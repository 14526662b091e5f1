#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_tools.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/scene/boundary_selector.h>

#include <cmath>
#include <limits>

namespace FetiContact
{
  using namespace dealii;

  BoundarySelector
  BoundarySelector::parse(const std::string &text_in, const std::string &what)
  {
    BoundarySelector  s;
    const std::string text = InputParsing::trim(text_in);
    s.text                 = text;
    const auto eq          = text.find('=');
    if (eq == std::string::npos)
      {
        char      *end = nullptr;
        const long v   = std::strtol(text.c_str(), &end, 10);
        require(!text.empty() && *end == '\0' && v >= 0 && v < interface_boundary_id,
                (what + ": <" + text +
                 "> is neither a boundary id (0…253) nor a plane such as "
                 "'x = xmin' or 'z = 0.5'."));
        s.kind = Kind::boundary_id;
        s.id   = static_cast<types::boundary_id>(v);
        return s;
      }
    const std::string lhs = InputParsing::trim(text.substr(0, eq));
    const std::string rhs = InputParsing::trim(text.substr(eq + 1));
    require(lhs == "x" || lhs == "y" || lhs == "z",
            (what + ": <" + text + "> should start with x, y or z, as in 'x = xmin'."));
    s.kind = Kind::plane;
    s.axis = lhs[0] - 'x';
    if (rhs == lhs + "min")
      s.bound = -1;
    else if (rhs == lhs + "max")
      s.bound = +1;
    else
      {
        s.bound = 0;
        s.value = InputParsing::parse_double(rhs, what + " <" + text + ">");
      }
    return s;
  }

  void
  BoundarySelector::resolve(const Triangulation<3>          &mesh,
                            const std::string               &body_name,
                            const MPI_Comm                   comm,
                            const Parameters::MeshTransform &body_frame)
  {
    frame = body_frame;
    if (kind == Kind::boundary_id)
      {
        const auto ids   = mesh.get_boundary_ids();
        const bool found = std::find(ids.begin(), ids.end(), id) != ids.end();
        require(Utilities::MPI::logical_or(found, comm),
                ("Body '" + body_name + "': boundary id " + std::to_string(id) +
                 " is used in the scene but the mesh has no boundary face with "
                 "this id."));
        return;
      }
    // The bounding box of the body's vertices (of every rank's cells), in its own frame.
    const double inf = std::numeric_limits<double>::infinity();
    Point<3>     lower(inf, inf, inf), upper(-inf, -inf, -inf);
    for (unsigned int v = 0; v < mesh.n_vertices(); ++v)
      if (mesh.get_used_vertices()[v])
        {
          const Point<3> x = frame.to_body(mesh.get_vertices()[v]);
          for (unsigned int d = 0; d < 3; ++d)
            {
              lower[d] = std::min(lower[d], x[d]);
              upper[d] = std::max(upper[d], x[d]);
            }
        }
    for (unsigned int d = 0; d < 3; ++d)
      {
        lower[d] = Utilities::MPI::min(lower[d], comm);
        upper[d] = Utilities::MPI::max(upper[d], comm);
      }
    if (bound < 0)
      value = lower[axis];
    else if (bound > 0)
      value = upper[axis];
    tolerance = 1e-8 * lower.distance(upper);

    bool found = false;
    for (const auto &cell : mesh.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary() && contains(*face))
          {
            found = true;
            break;
          }
    require(Utilities::MPI::logical_or(found, comm),
            ("Body '" + body_name + "': no boundary face lies in the plane <" + text + ">."));
  }

  bool
  BoundarySelector::contains(const TriaAccessor<2, 3, 3> &face) const
  {
    if (face.boundary_id() == interface_boundary_id)
      return false;
    if (kind == Kind::boundary_id)
      return face.boundary_id() == id;
    for (const unsigned int v : face.vertex_indices())
      if (std::abs(frame.to_body(face.vertex(v))[axis] - value) > tolerance)
        return false;
    return true;
  }
} // namespace FetiContact
