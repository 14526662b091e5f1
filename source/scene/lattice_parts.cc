#include <feticontact/scene/boundary_selector.h>
#include <feticontact/scene/lattice_parts.h>
#include <feticontact/scene/mesh_generation.h>

#include <algorithm>
#include <unordered_map>

namespace FetiContact
{
  using namespace dealii;

  std::optional<LatticeParts>
  LatticeParts::of(const Parameters::Body &body)
  {
    using Method     = Parameters::Decomposition::Method;
    const auto &mesh = body.mesh;
    const auto &n    = mesh.subdivisions;
    if (mesh.type != Parameters::Mesh::Type::box || mesh.tetrahedra_per_cube != 6)
      return {};
    std::array<unsigned int, 3> blocks;
    if (body.decomposition.method == Method::automatic)
      blocks = Parameters::Decomposition::automatic_blocks(n);
    else if (body.decomposition.method == Method::blocks && mesh.grading == 0 &&
             mesh.spherical_bottom_radius == 0)
      blocks = body.decomposition.blocks;
    else
      return {};
    for (unsigned int d = 0; d < 3; ++d)
      if (blocks[d] == 0 || blocks[d] > n[d] ||
          (body.decomposition.method == Method::blocks && n[d] % blocks[d] != 0))
        return {};
    return LatticeParts(mesh, blocks);
  }

  LatticeParts::LatticeParts(const Parameters::Mesh &mesh, const std::array<unsigned int, 3> &b)
    : mesh(mesh)
    , n(mesh.subdivisions)
    , blocks(b)
  {
    for (unsigned int d = 0; d < 3; ++d)
      {
        first_cube[d].assign(blocks[d] + 1, n[d]);
        for (unsigned int i = n[d]; i-- > 0;)
          first_cube[d][std::min(blocks[d] - 1, i * blocks[d] / n[d])] = i;
      }
  }

  std::array<unsigned int, 3>
  LatticeParts::block_of_part(const unsigned int part) const
  {
    return {{part % blocks[0], (part / blocks[0]) % blocks[1], part / (blocks[0] * blocks[1])}};
  }

  unsigned int
  LatticeParts::n_cells(const unsigned int part) const
  {
    const auto   b     = block_of_part(part);
    unsigned int cubes = 1;
    for (unsigned int d = 0; d < 3; ++d)
      cubes *= first_cube[d][b[d] + 1] - first_cube[d][b[d]];
    return 6 * cubes;
  }

  unsigned int
  LatticeParts::n_cells() const
  {
    return 6 * n[0] * n[1] * n[2];
  }

  unsigned int
  LatticeParts::n_vertices() const
  {
    return (n[0] + 1) * (n[1] + 1) * (n[2] + 1);
  }

  std::vector<unsigned int>
  LatticeParts::holders(const std::array<unsigned int, 3> &i) const
  {
    // Per axis the blocks of the cubes i − 1 and i that exist.
    std::array<std::vector<unsigned int>, 3> along;
    for (unsigned int d = 0; d < 3; ++d)
      for (unsigned int cube = (i[d] > 0 ? i[d] - 1 : 0); cube <= std::min(i[d], n[d] - 1); ++cube)
        {
          const unsigned int b = std::min(blocks[d] - 1, cube * blocks[d] / n[d]);
          if (along[d].empty() || along[d].back() != b)
            along[d].push_back(b);
        }
    std::vector<unsigned int> parts;
    for (const unsigned int bz : along[2])
      for (const unsigned int by : along[1])
        for (const unsigned int bx : along[0])
          parts.push_back(bx + blocks[0] * (by + blocks[1] * bz));
    std::sort(parts.begin(), parts.end());
    return parts;
  }

  PartCells
  LatticeParts::part_cells(const unsigned int part) const
  {
    const auto b = block_of_part(part);
    PartCells  result;
    result.part = part;
    std::unordered_map<unsigned int, unsigned int> local_vertex;
    const auto lattice_number = [&](const std::array<unsigned int, 3> &i) {
      return i[0] + (n[0] + 1) * (i[1] + (n[1] + 1) * i[2]);
    };
    for (unsigned int k = first_cube[2][b[2]]; k < first_cube[2][b[2] + 1]; ++k)
      for (unsigned int j = first_cube[1][b[1]]; j < first_cube[1][b[1] + 1]; ++j)
        for (unsigned int i = first_cube[0][b[0]]; i < first_cube[0][b[0] + 1]; ++i)
          for (unsigned int t = 0; t < 6; ++t)
            {
              const auto vertex = MeshGeneration::kuhn_tetrahedron(
                n, mesh.lower_corner, mesh.upper_corner, {{i, j, k}}, t);
              std::array<unsigned int, 4> local;
              for (unsigned int v = 0; v < 4; ++v)
                {
                  const unsigned int number = lattice_number(vertex[v]);
                  const auto [entry, first_seen] =
                    local_vertex.emplace(number, result.points.size());
                  if (first_seen)
                    {
                      result.add_vertex(mesh.transform(MeshGeneration::graded_point(
                                          MeshGeneration::kuhn_lattice_point(
                                            n, mesh.lower_corner, mesh.upper_corner, vertex[v]),
                                          mesh.lower_corner,
                                          mesh.upper_corner,
                                          mesh.focus,
                                          mesh.grading,
                                          mesh.spherical_bottom_radius)),
                                        number,
                                        holders(vertex[v]));
                    }
                  local[v] = entry->second;
                }
              result.cells.push_back(local);
              result.body_cell.push_back(6 * (i + n[0] * (j + n[1] * k)) + t);
              // Face f of a tetrahedron has every vertex but 3 − f. A face in a side of the box
              // gets the side's boundary id (2d at the lower end of axis d, 2d + 1 at the upper).
              for (unsigned int f = 0; f < 4; ++f)
                {
                  std::array<unsigned int, 3> face;
                  std::array<unsigned int, 3> corner;
                  for (unsigned int v = 0, m = 0; v < 4; ++v)
                    if (v != 3 - f)
                      {
                        face[m]   = local[v];
                        corner[m] = v;
                        ++m;
                      }
                  std::optional<types::boundary_id> id;
                  for (unsigned int d = 0; d < 3; ++d)
                    for (const unsigned int end : {0u, n[d]})
                      if (vertex[corner[0]][d] == end && vertex[corner[1]][d] == end &&
                          vertex[corner[2]][d] == end)
                        id = 2 * d + (end == 0 ? 0 : 1);
                  if (!id)
                    continue;
                  std::sort(face.begin(), face.end());
                  result.boundary_faces.emplace_back(face, *id);
                }
            }
    return result;
  }
} // namespace FetiContact
