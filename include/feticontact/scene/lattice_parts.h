#pragma once

#include <feticontact/scene/body_parameters.h>
#include <feticontact/scene/part_cells.h>

#include <array>
#include <optional>
#include <vector>

namespace FetiContact
{
  /**
   * The partition of a generated box (six tetrahedra per cube, MeshGeneration::
   * subdivided_box_kuhn()) into blocks of whole cubes, known without the mesh: the parts are
   * numbered b_x + B_x (b_y + B_y b_z), cube i of axis d lies in block min(B_d − 1, i B_d / n_d),
   * and a vertex lies in the blocks of the cubes around it. It lets every rank make the cells of
   * its own parts, the same PartCells to the bit that Body::part_cells() cuts from the whole mesh
   * (`unit.distributed_body_mpi` compares them), with the body's numbers of vertices and cells.
   */
  class LatticeParts
  {
  public:
    /**
     * The lattice blocks of body @p body, if its mesh and partition are such blocks: a box of six
     * tetrahedra per cube, decomposed automatically, or by Decomposition/Blocks that divide the
     * subdivisions of an undistorted box (the cut by cell centres is then the cut by cubes).
     */
    static std::optional<LatticeParts>
    of(const Parameters::Body &body);

    /** The number of parts. */
    unsigned int
    n_parts() const
    {
      return blocks[0] * blocks[1] * blocks[2];
    }

    /** The number of cells of part @p part. */
    unsigned int
    n_cells(const unsigned int part) const;

    /** The numbers of cells and vertices of the whole box. */
    unsigned int
    n_cells() const;
    unsigned int
    n_vertices() const;

    /** The cells of part @p part, moved by the body's Mesh/Transform. */
    PartCells
    part_cells(const unsigned int part) const;

  private:
    LatticeParts(const Parameters::Mesh &mesh, const std::array<unsigned int, 3> &blocks);

    /** The blocks of part @p part along the three axes. */
    std::array<unsigned int, 3>
    block_of_part(const unsigned int part) const;

    /** The parts that hold the lattice point @p i, increasing. */
    std::vector<unsigned int>
    holders(const std::array<unsigned int, 3> &i) const;

    Parameters::Mesh            mesh;
    std::array<unsigned int, 3> n, blocks;
    /** Per axis and block: its first cube, and the end of the last block (B_d + 1 entries). */
    std::array<std::vector<unsigned int>, 3> first_cube;
  };
} // namespace FetiContact
