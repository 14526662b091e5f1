#include <deal.II/grid/grid_tools.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/scene/decomposition.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    /** Splits every part into its face-connected components; empty parts disappear. */
    CellPartition
    face_connected_components(const Triangulation<3> &mesh, const std::vector<unsigned int> &part)
    {
      const unsigned int        unset = numbers::invalid_unsigned_int;
      std::vector<unsigned int> component(mesh.n_active_cells(), unset);
      unsigned int              n = 0;
      // Seeds in the order of the original parts, so that a partition that needs no split keeps
      // its numbering.
      std::vector<std::vector<unsigned int>> cells_of_part;
      for (const auto &cell : mesh.active_cell_iterators())
        {
          const unsigned int p = part[cell->active_cell_index()];
          if (p >= cells_of_part.size())
            cells_of_part.resize(p + 1);
          cells_of_part[p].push_back(cell->active_cell_index());
        }
      std::vector<typename Triangulation<3>::active_cell_iterator> cell_of_index(
        mesh.n_active_cells());
      for (const auto &cell : mesh.active_cell_iterators())
        cell_of_index[cell->active_cell_index()] = cell;

      for (const auto &cells : cells_of_part)
        for (const unsigned int seed : cells)
          if (component[seed] == unset)
            {
              std::queue<unsigned int> queue;
              queue.push(seed);
              component[seed] = n;
              while (!queue.empty())
                {
                  const auto cell = cell_of_index[queue.front()];
                  queue.pop();
                  for (const unsigned int f : cell->face_indices())
                    if (!cell->at_boundary(f))
                      {
                        const unsigned int nb = cell->neighbor(f)->active_cell_index();
                        if (component[nb] == unset && part[nb] == part[cell->active_cell_index()])
                          {
                            component[nb] = n;
                            queue.push(nb);
                          }
                      }
                }
              ++n;
            }
      return {component, n};
    }

    /**
     * Gives every face-connected piece of a part but its largest to the part it shares the most
     * faces with, until each part is one piece. A cut by coordinates (blocks) through a graded
     * or curved mesh, or a METIS part, leaves such pieces, down to single tetrahedra; as
     * subdomains of their own they multiply the rigid body modes and make the dual problem
     * nearly singular (85 subdomains for Blocks = 2, 2, 2 on the graded Cattaneo–Mindlin mesh).
     * Pieces without a neighbour in another part (a body made of disconnected meshes) stay.
     */
    std::vector<unsigned int>
    merge_fragments(const Triangulation<3> &mesh, std::vector<unsigned int> part)
    {
      for (unsigned int round = 0; round < 100; ++round)
        {
          const CellPartition       pieces = face_connected_components(mesh, part);
          std::vector<unsigned int> size(pieces.n_parts, 0), largest(pieces.n_parts, 0);
          std::vector<unsigned int> part_of_piece(pieces.n_parts, 0);
          for (const auto &cell : mesh.active_cell_iterators())
            {
              const unsigned int c = cell->active_cell_index();
              ++size[pieces.part_of_cell[c]];
              part_of_piece[pieces.part_of_cell[c]] = part[c];
            }
          // The largest piece of every part (the first of equal size) is its main piece.
          std::map<unsigned int, unsigned int> main_piece;
          for (unsigned int q = 0; q < pieces.n_parts; ++q)
            {
              const auto [it, first] = main_piece.emplace(part_of_piece[q], q);
              if (!first && size[q] > size[it->second])
                it->second = q;
            }
          // Faces shared by each fragment with the parts around it (a tetrahedron has four).
          std::vector<std::map<unsigned int, unsigned int>> shared(pieces.n_parts);
          for (const auto &cell : mesh.active_cell_iterators())
            {
              const unsigned int c = cell->active_cell_index();
              const unsigned int q = pieces.part_of_cell[c];
              if (main_piece[part[c]] == q)
                continue;
              for (const unsigned int f : cell->face_indices())
                if (!cell->at_boundary(f))
                  {
                    const unsigned int nb = cell->neighbor(f)->active_cell_index();
                    // Faces with the main piece of a part count first: a fragment that
                    // joins another fragment could swap parts with it forever.
                    if (part[nb] != part[c])
                      shared[q][part[nb]] +=
                        main_piece[part[nb]] == pieces.part_of_cell[nb] ? 1u << 16 : 1u;
                  }
            }
          std::vector<unsigned int> target(pieces.n_parts, numbers::invalid_unsigned_int);
          bool                      changed = false;
          for (unsigned int q = 0; q < pieces.n_parts; ++q)
            {
              unsigned int most = 0;
              for (const auto &[p, n_faces] : shared[q])
                if (n_faces > most)
                  {
                    most      = n_faces;
                    target[q] = p;
                  }
              changed = changed || most > 0;
            }
          if (!changed)
            break;
          for (const auto &cell : mesh.active_cell_iterators())
            {
              const unsigned int c = cell->active_cell_index();
              const unsigned int q = pieces.part_of_cell[c];
              if (target[q] != numbers::invalid_unsigned_int)
                part[c] = target[q];
            }
        }
      return part;
    }
  } // namespace

  std::vector<std::vector<unsigned int>>
  parts_of_vertices(const Triangulation<3> &mesh, const CellPartition &partition)
  {
    std::vector<std::vector<unsigned int>> parts(mesh.n_vertices());
    for (const auto &cell : mesh.active_cell_iterators())
      {
        const unsigned int p = partition.part_of_cell[cell->active_cell_index()];
        for (const unsigned int v : cell->vertex_indices())
          {
            auto &list = parts[cell->vertex_index(v)];
            if (std::find(list.begin(), list.end(), p) == list.end())
              list.push_back(p);
          }
      }
    for (auto &list : parts)
      std::sort(list.begin(), list.end());
    return parts;
  }

  namespace
  {
    /**
     * The parts of the cells of a generated box of @p n cubes cut into @p blocks blocks of
     * (nearly) equally many cubes. The cube of a cell comes from its vertices' indices, which
     * the box keeps in lexicographic order (i + (n_x + 1)(j + (n_y + 1) k)): per axis the
     * smallest lattice index of the cell's vertices (a tetrahedron of a cube never lies in one
     * of its faces). So the cut follows the cubes, also where grading or bending moved them.
     */
    std::vector<unsigned int>
    lattice_blocks(const Triangulation<3>            &mesh,
                   const std::array<unsigned int, 3> &n,
                   const std::array<unsigned int, 3> &blocks)
    {
      std::vector<unsigned int> part(mesh.n_active_cells(), 0);
      for (const auto &cell : mesh.active_cell_iterators())
        {
          std::array<unsigned int, 3> cube{{n[0], n[1], n[2]}};
          for (const unsigned int v : cell->vertex_indices())
            {
              const unsigned int index      = cell->vertex_index(v);
              const unsigned int lattice[3] = {index % (n[0] + 1),
                                               (index / (n[0] + 1)) % (n[1] + 1),
                                               index / ((n[0] + 1) * (n[1] + 1))};
              for (unsigned int d = 0; d < 3; ++d)
                cube[d] = std::min(cube[d], lattice[d]);
            }
          unsigned int b[3];
          for (unsigned int d = 0; d < 3; ++d)
            b[d] = std::min(blocks[d] - 1, cube[d] * blocks[d] / n[d]);
          part[cell->active_cell_index()] = b[0] + blocks[0] * (b[1] + blocks[1] * b[2]);
        }
      return part;
    }
  } // namespace

  CellPartition
  partition_cells(const Triangulation<3>          &mesh,
                  const Parameters::Decomposition &parameters,
                  const Parameters::Mesh          &mesh_parameters,
                  const std::string               &body_name)
  {
    using Method = Parameters::Decomposition::Method;
    std::vector<unsigned int> part(mesh.n_active_cells(), 0);
    if (parameters.method == Method::automatic &&
        mesh_parameters.type == Parameters::Mesh::Type::box)
      part =
        lattice_blocks(mesh,
                       mesh_parameters.subdivisions,
                       Parameters::Decomposition::automatic_blocks(mesh_parameters.subdivisions));
    else if (parameters.method == Method::blocks)
      {
        const auto  box   = GridTools::compute_bounding_box(mesh);
        const auto  lower = box.get_boundary_points().first;
        const auto  upper = box.get_boundary_points().second;
        const auto &nb    = parameters.blocks;
        require(static_cast<std::size_t>(nb[0]) * nb[1] * nb[2] <= mesh.n_active_cells(),
                "Body '" + body_name +
                  "': Decomposition/Blocks asks for more subdomains than "
                  "the mesh has cells (" +
                  std::to_string(mesh.n_active_cells()) + ").");
        for (const auto &cell : mesh.active_cell_iterators())
          {
            const Point<3> c = cell->center();
            unsigned int   b[3];
            for (unsigned int d = 0; d < 3; ++d)
              {
                const double t = (c[d] - lower[d]) / (upper[d] - lower[d]);
                b[d]           = std::min<unsigned int>(nb[d] - 1,
                                              static_cast<unsigned int>(std::floor(t * nb[d])));
              }
            part[cell->active_cell_index()] = b[0] + nb[0] * (b[1] + nb[1] * b[2]);
          }
      }
    else
      {
        unsigned int n_parts = parameters.n_parts_for(mesh_parameters, mesh.n_used_vertices());
        if (parameters.method == Method::automatic)
          n_parts = std::min(n_parts, mesh.n_active_cells());
        require(n_parts <= mesh.n_active_cells(),
                "Body '" + body_name + "': Decomposition/Number of parts (" +
                  std::to_string(n_parts) + ") exceeds the number of cells (" +
                  std::to_string(mesh.n_active_cells()) + ").");
        if (n_parts > 1)
          {
            Triangulation<3> &m = const_cast<Triangulation<3> &>(mesh);
            GridTools::partition_triangulation(n_parts, m, SparsityTools::Partitioner::metis);
            for (const auto &cell : mesh.active_cell_iterators())
              part[cell->active_cell_index()] = cell->subdomain_id();
          }
      }
    return face_connected_components(mesh, merge_fragments(mesh, part));
  }
} // namespace FetiContact
