#include <feticontact/base/input_parsing.h>
#include <feticontact/scene/body.h>
#include <feticontact/scene/mesh_generation.h>
#include <feticontact/subdomain/rigid_body_modes.h>

#include <cmath>
#include <sstream>

namespace FetiContact
{
  using namespace dealii;

  Body::Body(const Parameters::Body &parameters, const unsigned int index)
    : parameters(parameters)
    , index(index)
  {}

  void
  Body::setup()
  {
    MeshGeneration::create_mesh(parameters.mesh, mesh, parameters.name);

    auto &bc = parameters.boundary_conditions;
    for (auto &p : bc.prescribed_displacements)
      p.boundary.resolve(mesh, parameters.name);
    for (auto &t : bc.tractions)
      t.boundary.resolve(mesh, parameters.name);

    // Γ_u vertex by vertex; two parts that prescribe different values for the same component
    // of a vertex contradict each other.
    prescribed.clear();
    std::map<unsigned int, std::array<const Parameters::PrescribedDisplacement *, 3>> source;
    for (const auto &cell : mesh.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          for (const auto &p : bc.prescribed_displacements)
            if (p.boundary.contains(*face))
              for (const unsigned int v : face->vertex_indices())
                {
                  const unsigned int vertex = face->vertex_index(v);
                  auto              &value  = prescribed[vertex];
                  auto              &from   = source[vertex];
                  for (unsigned int c = 0; c < 3; ++c)
                    if (p.value[c])
                      {
                        if (value[c] && from[c] != &p)
                          {
                            const double a = *value[c], b = *p.value[c];
                            require(std::abs(a - b) <= 1e-12 * std::max(std::abs(a), std::abs(b)),
                                    "Body '" + parameters.name + "': the boundary parts <" +
                                      from[c]->boundary.name() + "> and <" + p.boundary.name() +
                                      "> prescribe different displacements (" +
                                      InputParsing::number_text(a) + " and " +
                                      InputParsing::number_text(b) + ") for component " +
                                      std::to_string(c) + " at the vertex they share.");
                          }
                        value[c] = p.value[c];
                        from[c]  = &p;
                      }
                }

    partition = partition_cells(mesh, parameters.decomposition, parameters.name);
    cells_of_part.assign(partition.n_parts, {});
    for (const auto &cell : mesh.active_cell_iterators())
      cells_of_part[partition.part_of_cell[cell->active_cell_index()]].push_back(cell);
  }

  void
  Body::check_held() const
  {
    std::vector<Point<3>>     points;
    std::vector<unsigned int> components;
    std::vector<bool>         fixed;
    // The motion is determined by the vertices; use all of them (a large body has enough
    // independent points; the check needs only that the fixed DoFs remove every motion).
    for (unsigned int v = 0; v < mesh.n_vertices(); ++v)
      {
        if (!mesh.get_used_vertices()[v])
          continue;
        const auto it = prescribed.find(v);
        for (unsigned int c = 0; c < 3; ++c)
          {
            points.push_back(mesh.get_vertices()[v]);
            components.push_back(c);
            fixed.push_back(it != prescribed.end() && it->second[c].has_value());
          }
      }
    const auto R = rigid_body_modes(points, components, fixed);
    require(R.n() == 0,
            "Body '" + parameters.name + "' is not held: its prescribed displacements leave " +
              std::to_string(R.n()) +
              " rigid body motion(s) free and the scene has no contact, so the linear elastic "
              "problem has no unique solution (equilibrium of the loads is not guaranteed). "
              "Clamp or prescribe displacements on a larger part of its boundary.");
  }

  unsigned int
  Body::n_free_dofs() const
  {
    unsigned int n = 3 * mesh.n_used_vertices();
    for (const auto &[v, value] : prescribed)
      for (const auto &c : value)
        if (c)
          --n;
    return n;
  }
} // namespace FetiContact
