#pragma once

#include <deal.II/base/tensor.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>

#include <feticontact/contact/contact_geometry.h>
#include <feticontact/contact/contact_results.h>
#include <feticontact/postprocessing/output_parameters.h>
#include <feticontact/scene/body.h>

#include <memory>
#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * The scales of a nondimensional FCLIB problem (all 1 in SI units): a length scale L and a
   * stress scale S. Two products are chosen: the stiffness scale S L = E_max h_c, which makes
   * the entries of M / (S L) of order one, and the force scale S L², the size of the load, which
   * makes f / (S L²) of order one. L and S follow from them.
   */
  struct FclibScales
  {
    /** E_max, the largest Young's modulus of the bodies [Pa]. */
    double youngs_modulus = 1;
    /** h_c, the square root of the slave contact area per contact node [m]. */
    double contact_spacing = 1;
    /** The stiffness scale S L = E_max h_c [N/m]. */
    double stiffness = 1;
    /**
     * The force scale S L² = max(max |f|, E_max h_c max |w|) [N]: the largest load, or the force
     * that moves a node by the largest gap or prescribed offset if that is larger; E_max h_c²
     * if f and w vanish.
     */
    double force = 1;
    /** The length scale L = S L² / (S L) [m]: the displacement of a node under the force scale. */
    double length = 1;
    /** The stress scale S = (S L)² / (S L²) [Pa]. */
    double stress = 1;
  };

  /**
   * The discrete contact problem of a scene in the global form of the Frictional Contact Library
   * (FCLIB, https://frictionalcontactlibrary.github.io), with the solution computed here:
   * find v, u, r with
   *
   *   M v = H r + f,   û = Hᵀ v + w + [μ‖u_T‖, 0, 0] per contact,   C*_μ ∋ û ⊥ r ∈ C_μ,
   *
   * C_μ = {r : ‖r_T‖ ≤ μ r_N} the Coulomb cone of each contact and C*_μ its dual. Here
   * - v: the displacements of the free DoFs of all bodies, undecomposed (no FETI), body by body
   *   and, within a body, by the DoF numbering of a DoFHandler on the body's whole mesh; DoFs with
   *   a prescribed displacement are removed;
   * - M: the P1 stiffness of each body's whole mesh on the free DoFs (block diagonal over the
   *   bodies; only positive semidefinite for a body held by contact alone), f: the loads minus
   *   the coupling to the prescribed displacements, f_free − K_free,prescribed ū;
   * - per contact node k, the frame [n_k, t1_k, t2_k] (first component normal): column 3k + c
   *   of H is −e_c at the slave vertex's free DoFs and +e_c at the master vertex's (none for a
   *   rigid obstacle), e_0 = n, e_1 = t1, e_2 = t2; w_3k = d_k (the initial gap) and the prescribed
   *   displacements' part of −e_c·(u_slave − u_master). So u_N = d − n·(u_slave − u_master) ≥ 0 is
   *   the separation (FCLIB's convention), u_T the tangential displacement of the master relative
   *   to the slave, and r = (λ_N, λ_T1, λ_T2) the force of the obstacle on the slave body in the
   *   frame, pushing it away: the force on the slave is −(r_N n + r_T1 t1 + r_T2 t2);
   * - μ: the friction coefficient of each node's zone.
   *
   * In SI units v, u, w are metres, r, f newtons and M newtons per metre. Nondimensional
   * (fclib_scales(), nondimensionalise()): v, u, w are divided by a length scale L, r and f by
   * the force scale S L² and M by S L, S a stress scale; H and μ are dimensionless and
   * unchanged, so the scaled data and solution satisfy the same equations.
   */
  struct FclibProblem
  {
    /** A sparse matrix in compressed columns (FCLIB's nz = −1): column pointers, rows, values. */
    struct CompressedColumns
    {
      int                 n_rows = 0, n_columns = 0;
      std::vector<int>    column_start, row;
      std::vector<double> value;
    };

    CompressedColumns   M, H;
    std::vector<double> f, w, mu;
    /** The solution: v (free DoFs), u = Hᵀ v + w and r (three per contact). */
    std::vector<double> v, u, r;

    /** The units of the stored values. */
    Parameters::Output::FclibUnits units = Parameters::Output::FclibUnits::SI;
    /**
     * The scales of the stored values: a stored length or displacement x is x L metres, a
     * stored force y is y S L² newtons, a stored entry m of M is m S L newtons per metre.
     */
    FclibScales scales;
  };

  /**
   * The scales of the nondimensional form of @p problem, the FCLIB problem of a scene in SI
   * units (its f and w; not its solution): E_max the largest Young's modulus of the @p bodies,
   * h_c = (Σ_k area_k / n_c)^(1/2) over the contact @p nodes (the spacing of the contact
   * nodes), S L = E_max h_c, S L² = max(max |f|, E_max h_c max |w|) (E_max h_c² if both are 0).
   */
  FclibScales
  fclib_scales(const std::vector<std::unique_ptr<Body>> &bodies,
               const std::vector<ContactNode>           &nodes,
               const FclibProblem                       &problem);

  /**
   * Divides @p problem, in SI units, by @p scales: v, u, w by L, r and f by S L², the entries
   * of M by S L (H and μ are dimensionless). Sets the problem's units to
   * nondimensional and stores the scales in it.
   */
  void
  nondimensionalise(FclibProblem &problem, const FclibScales &scales);

  /**
   * Assembles the global FCLIB problem of the scene from the bodies' whole meshes and the
   * contact nodes, and the solution from the displacements @p vertex_u (per body and vertex)
   * and the contact forces @p results of a solve, in the @p units asked for: SI, or divided by
   * the fclib_scales() of the scene.
   */
  FclibProblem
  assemble_fclib_problem(const std::vector<std::unique_ptr<Body>>             &bodies,
                         const std::vector<ContactNode>                       &nodes,
                         const std::vector<ContactNodeResult>                 &results,
                         const std::vector<std::vector<dealii::Tensor<1, 3>>> &vertex_u,
                         const dealii::Mapping<3>                             &mapping,
                         const dealii::FiniteElement<3>                       &fe,
                         const Parameters::Output::FclibUnits                  units);

  /** Whether this build can write FCLIB files (it found libfclib when configured). */
  bool
  fclib_available();

  /**
   * Writes @p problem and its solution to the HDF5 file @p file with libfclib
   * (fclib_write_global, fclib_write_solution), replacing an existing file. @p title and
   * @p description go into the problem's info, the description followed by a line with the
   * units and scales. The root group of the file gets the attributes `units` (the string
   * "nondimensional" or "SI"), `length_scale` L [m], `stress_scale` S [Pa] and `force_scale`
   * S L² [N] (doubles, 1 in SI units). Throws std::runtime_error if libfclib or HDF5 reports a
   * failure or the build has no FCLIB.
   */
  void
  write_fclib(const std::string  &file,
              const FclibProblem &problem,
              const std::string  &title,
              const std::string  &description);
} // namespace FetiContact
