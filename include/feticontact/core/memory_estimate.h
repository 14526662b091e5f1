#pragma once

#include <feticontact/scene/scene_parameters.h>

#include <mpi.h>
#include <string>

namespace FetiContact
{
  /**
   * A model of a run's peak resident memory per rank, from the sizes of its meshes alone, so
   * that a scene too large for the machine is refused before any mesh is built instead of being
   * killed by the system minutes later.
   *
   * For body b with C_b tetrahedra, V_b vertices and P_b parts (blocks or METIS), and np ranks:
   *
   *   M = M₀ + a Σ_b C_b + b_f s Σ_b P_b (3 v_b)^(4/3)  [+ b_f Σ_b (3 V_b)^(4/3) / r],
   *   v_b = ((∛V_b − 1) / ∛P_b + 1)³,  s = ⌈P / np⌉ / P,  P = Σ_b P_b,
   *
   * M₀: the program and its libraries; a: a cell of the replicated body meshes, the subdomain
   * meshes, DoF handlers, stiffness matrices and B rows; b_f: a unit of the Cholesky factors,
   * whose size grows like n^(4/3) for a subdomain of n unknowns (nested dissection in 3D), with
   * v_b the vertices of a part including the copies on its interfaces (the body as a cube cut
   * into P_b cubes) and s the largest rank's share of the parts; the bracket is the monolithic
   * verification solve, made by rank 0 for scenes without contact and shared among the r ranks
   * of its machine (the least number of ranks on a machine of the run). The coefficients are
   * fitted to measured peaks, which the model meets within 10 % (benchmarks/memory_model.py,
   * doc/performance.md, "Memory"); a run is refused only when even the estimate less 10 % exceeds
   * the memory available. Box meshes give C and V from their subdivisions, Gmsh files from the
   * counts in their $Nodes and $Elements headers.
   *
   * With the cells distributed over the ranks (FETI/Dual vectors = distributed, np > 1) the cell
   * term is the largest rank's share, s a Σ_b C_b, plus a_m C_b for every body whose mesh rank 0
   * creates whole (all but the blocks of generated boxes, LatticeParts), a_m the memory of a
   * cell of a whole mesh, and there is no monolithic solve.
   */
  struct MemoryEstimate
  {
    double peak_mib      = 0; ///< the model's peak resident memory per rank
    double available_mib = 0; ///< what this node's ranks can still use, per rank
    /** What limits available_mib: the machine's MemAvailable or a memory cgroup (this rank's). */
    std::string available_source;
    double      cells        = 0; ///< Σ C_b
    double      factor_units = 0; ///< the factor term's Σ before its coefficient, per rank
    /** The fraction of the subdivisions (boxes) or of the cells (Gmsh) that would fit; 0 if none.
     */
    double       fitting_scale = 1;
    unsigned int ranks_on_node = 1;

    /** The estimate of @p scene on @p comm (collective). */
    static MemoryEstimate
    of(const Parameters::Scene &scene, MPI_Comm comm);

    /** Whether the estimate less the model's error fits the memory available on every node. */
    bool
    fits() const;

    /** Whether the estimate itself exceeds the memory available (the run may be killed). */
    bool
    tight() const;

    /**
     * Throws InputError naming the estimate, the memory available and the mesh size that fits
     * unless fits(). The estimate is the same on every rank: all of them throw or none.
     */
    void
    check(const Parameters::Scene &scene) const;
  };
} // namespace FetiContact
