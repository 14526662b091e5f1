// A body whose cells are distributed over the ranks (Body::create_and_partition with
// distributed = true, then distribute and set_up_boundary): on P ranks, each owning a contiguous
// range of the parts, a rank's mesh must hold exactly the cells of its own parts, and what it
// derives from them must be what one rank holding the whole mesh derives: the PartCells of its
// parts (positions, body vertex numbers, holders, cells, boundary faces), Γ_u at every vertex it
// holds (also where only another rank's cells touch the prescribed faces: METIS parts meet the
// boundary at single vertices), the counts, the free rigid motions, the free DoFs and the work
// of the loads. Blocks and METIS, with rollers on two faces besides the clamp; with 40 METIS
// parts some rank holds a prescribed vertex whose prescribed faces only other ranks hold. The
// blocks of a generated box are made by every rank for itself (LatticeParts), which must give
// the same cells, to the bit, as the cut of the whole mesh, also for a graded and bent box.

#include <deal.II/base/mpi.h>

#include <feticontact/scene/body.h>
#include <feticontact/scene/lattice_parts.h>

#include "test_tools.h"

#include <cmath>

using namespace dealii;
using namespace FetiContact;

namespace
{
  bool
  same(const PartCells &a, const PartCells &b)
  {
    return a.part == b.part && a.points == b.points && a.body_vertex == b.body_vertex &&
           a.holder_start == b.holder_start && a.holder_parts == b.holder_parts &&
           a.cells == b.cells && a.body_cell == b.body_cell && a.boundary_faces == b.boundary_faces;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                   world   = MPI_COMM_WORLD;
  const unsigned int               n_ranks = Utilities::MPI::n_mpi_processes(world);
  const unsigned int               rank    = Utilities::MPI::this_mpi_process(world);

  // The blocks of a box made without the mesh against the cut of the whole mesh.
  for (const auto &[name, settings] : std::vector<std::pair<std::string, std::string>>{
         {"automatic blocks", "set Method = automatic"},
         {"blocks 3 × 2 × 2", "set Method = blocks\nset Blocks = 3, 2, 2"},
         {"automatic blocks, graded and bent box",
          "set Method = automatic\n end\n subsection Mesh\n set Grading = 2\n"
          " set Spherical bottom radius = 5\n set Focus = 1, 0.5"}})
    {
      const auto scene   = scene_from_text(brick_text(settings, 6));
      const auto lattice = LatticeParts::of(scene.bodies[0]);
      Body       whole(scene.bodies[0], 0);
      whole.setup();
      bool same_parts = lattice.has_value() && lattice->n_parts() == whole.partition.n_parts &&
                        lattice->n_cells() == whole.n_cells &&
                        lattice->n_vertices() == whole.n_vertices;
      const auto parts = whole.parts_of_mesh_vertices();
      for (unsigned int p = 0; same_parts && p < whole.partition.n_parts; ++p)
        same_parts = lattice->n_cells(p) == whole.cells_per_part[p] &&
                     same(lattice->part_cells(p), whole.part_cells(p, parts));
      check(same_parts,
            name + ": every part made without the mesh is the cut of the whole mesh (" +
              std::to_string(whole.partition.n_parts) + " parts)");
    }
  check(!LatticeParts::of(
          scene_from_text(brick_text("set Method = blocks\nset Blocks = 5, 1, 1")).bodies[0]),
        "blocks that do not divide the cubes are not made without the mesh");

  for (const auto &[name, decomposition] : std::vector<std::pair<std::string, std::string>>{
         {"blocks 3 × 2 × 2", "set Method = blocks\nset Blocks = 3, 2, 2"},
         {"METIS 9", "set Method = metis\nset Number of parts = 9"},
         {"METIS 40", "set Method = metis\nset Number of parts = 40"}})
    {
      std::string       text    = brick_text(decomposition);
      const std::string clamped = "  set Clamped boundaries = x = xmin\n";
      text.replace(text.find(clamped),
                   clamped.size(),
                   clamped + "  set Prescribed displacements = y = ymin: free, 0, free; "
                             "z = zmin: free, free, 0\n");
      const auto scene = scene_from_text(text);
      Body       whole(scene.bodies[0], 0);
      whole.setup();
      Body spread(scene.bodies[0], 0);
      spread.create_and_partition(world);
      const unsigned int n_parts = spread.partition.n_parts;
      const auto         owner   = [&](const unsigned int p) { return p * n_ranks / n_parts; };
      spread.distribute(owner);
      spread.set_up_boundary();
      const std::string on = name + " on " + std::to_string(n_ranks) + " rank(s): ";

      check(spread.n_cells == whole.n_cells && spread.n_vertices == whole.n_vertices &&
              spread.cells_per_part == whole.cells_per_part,
            on + "the counts of the whole body");
      unsigned int own_cells  = 0;
      bool         same_parts = true;
      for (unsigned int p = 0; p < n_parts; ++p)
        if (owner(p) == rank)
          {
            own_cells += whole.cells_per_part[p];
            same_parts = same_parts && same(spread.part_cells(p), whole.part_cells(p));
          }
      check(spread.mesh.n_active_cells() == own_cells &&
              (n_ranks == 1 || own_cells < whole.n_cells),
            on + std::to_string(spread.mesh.n_active_cells()) +
              " cells held, those of the own parts: " + std::to_string(own_cells) + " of " +
              std::to_string(whole.n_cells));
      check(same_parts, on + "the cells of the own parts as the whole mesh cuts them");

      unsigned int n_different = 0, n_prescribed = 0;
      for (unsigned int v = 0; v < spread.mesh.n_vertices(); ++v)
        {
          const unsigned int w     = spread.body_vertex(v);
          const auto         mine  = spread.prescribed.find(w);
          const auto         their = whole.prescribed.find(w);
          const bool         here  = mine != spread.prescribed.end();
          if (here != (their != whole.prescribed.end()) || (here && mine->second != their->second))
            ++n_different;
          n_prescribed += here;
        }
      check(n_different == 0 && spread.prescribed.size() == n_prescribed && n_prescribed > 0,
            on + "Γ_u at every held vertex as on the whole mesh (" + std::to_string(n_different) +
              " different of " + std::to_string(n_prescribed) + ")");

      const auto         motions       = spread.free_rigid_motions();
      const auto         whole_motions = whole.free_rigid_motions();
      const unsigned int n_free        = spread.n_free_dofs();
      check(motions.n() == whole_motions.n() && n_free == whole.n_free_dofs(),
            on + std::to_string(motions.n()) + " free rigid motions, " + std::to_string(n_free) +
              " free DoFs, as on the whole mesh");
      // A body free along x (only rollers) to test the work of the loads on a free motion.
      std::string free_text = text;
      free_text.replace(free_text.find(clamped), clamped.size(), "");
      const auto free_scene = scene_from_text(free_text);
      Body       free_whole(free_scene.bodies[0], 0);
      free_whole.setup();
      Body free_spread(free_scene.bodies[0], 0);
      free_spread.create_and_partition(world);
      free_spread.distribute(owner);
      free_spread.set_up_boundary();
      const auto m_whole  = free_whole.free_rigid_motions();
      const auto m_spread = free_spread.free_rigid_motions();
      const auto w_whole  = free_whole.load_work(m_whole);
      const auto w_spread = free_spread.load_work(m_spread);
      double     error    = 0;
      for (unsigned int j = 0; j < w_whole.size() && w_whole.size() == w_spread.size(); ++j)
        error = std::max(error, std::abs(w_whole[j] - w_spread[j]) / w_whole.linfty_norm());
      check(m_spread.n() == m_whole.n() && m_whole.n() > 0 && error == 0,
            on + "the work of the loads on the " + std::to_string(m_whole.n()) +
              " free motions of an unclamped body, the same bits (exact sums): relative "
              "difference " +
              sci(error));
    }
  const int failures = Utilities::MPI::max(n_failures, world);
  if (rank == 0)
    std::cout << (failures == 0 ? "PASSED" : "FAILED") << std::endl;
  return failures;
}
