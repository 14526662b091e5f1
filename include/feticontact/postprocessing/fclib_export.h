#pragma once

#include <deal.II/base/tensor.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>

#include <feticontact/contact/contact_geometry.h>
#include <feticontact/contact/contact_results.h>
#include <feticontact/scene/body.h>

#include <memory>
#include <string>
#include <vector>

namespace FetiContact
{
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
   * - μ: the friction coefficient F of each node's zone.
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
  };

  /**
   * Assembles the global FCLIB problem of the scene from the bodies' whole meshes and the
   * contact nodes, and the solution from the displacements @p vertex_u (per body and vertex)
   * and the contact forces @p results of a solve.
   */
  FclibProblem
  assemble_fclib_problem(const std::vector<std::unique_ptr<Body>>             &bodies,
                         const std::vector<ContactNode>                       &nodes,
                         const std::vector<ContactNodeResult>                 &results,
                         const std::vector<std::vector<dealii::Tensor<1, 3>>> &vertex_u,
                         const dealii::Mapping<3>                             &mapping,
                         const dealii::FiniteElement<3>                       &fe);

  /** Whether this build can write FCLIB files (it found libfclib when configured). */
  bool
  fclib_available();

  /**
   * Writes @p problem and its solution to the HDF5 file @p file with libfclib
   * (fclib_write_global, fclib_write_solution), replacing an existing file. @p title and
   * @p description go into the problem's info. Throws std::runtime_error if libfclib reports a
   * failure or the build has no FCLIB.
   */
  void
  write_fclib(const std::string  &file,
              const FclibProblem &problem,
              const std::string  &title,
              const std::string  &description);
} // namespace FetiContact
