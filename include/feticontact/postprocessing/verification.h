#pragma once

#include <deal.II/base/tensor.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/vector.h>

#include <feticontact/contact/contact_forces.h>
#include <feticontact/contact/contact_geometry.h>
#include <feticontact/scene/body.h>
#include <feticontact/subdomain/subdomain.h>

#include <array>
#include <mpi.h>
#include <vector>

namespace FetiContact
{
  /**
   * Displacements of every vertex of every body (x, y, z per vertex, by body and vertex number in
   * the body's whole mesh, up to the highest number a subdomain reports), gathered from the
   * subdomain solutions: a vertex shared by several subdomains takes the value of the
   * lowest-numbered one. Replicated on every rank.
   */
  std::vector<std::vector<dealii::Tensor<1, 3>>>
  gather_vertex_displacements(const MPI_Comm                             comm,
                              const std::vector<std::unique_ptr<Body>>  &bodies,
                              const std::vector<Subdomain *>            &owned,
                              const std::vector<dealii::Vector<double>> &u);

  /**
   * The linear elastic problem of one body without decomposition: the same P1 stiffness and
   * loads on the body's whole mesh, prescribed DoFs eliminated, solved by CHOLMOD. Returns the
   * displacement of every vertex.
   */
  std::vector<dealii::Tensor<1, 3>>
  solve_monolithic(const Body                     &body,
                   const dealii::Mapping<3>       &mapping,
                   const dealii::FiniteElement<3> &fe);

  /** Differences of the displacements from reference displacements on the same meshes. */
  struct ReferenceDifference
  {
    /** max_v ‖u(v) − u_ref(v)‖ / max_v ‖u_ref(v)‖ over all vertices. */
    double max_relative = 0;
    /** ‖u − u_ref‖_K / ‖u_ref‖_K, with ‖v‖_K² = vᵀKv for the stiffness K of every body. */
    double       energy_relative = 0;
    unsigned int n_vertices      = 0;
  };

  /**
   * Reads @p file, a displacements.csv (columns body, x, y, z, ux, uy, uz; without the body
   * column every row belongs to body 0) and matches its rows to the vertices of the bodies by
   * position (to 1e-9 of each body's size). Throws InputError, naming the file and the point,
   * if a vertex has no row or the file is malformed. Returns the displacement of each vertex of
   * the cells this rank holds. Collective.
   */
  VertexDisplacements
  read_reference_displacements(const std::string                        &file,
                               const std::vector<std::unique_ptr<Body>> &bodies);

  /**
   * The difference of the displacements @p u of this rank's subdomains @p owned from
   * @p reference: the largest over the vertices (each counted once, by the subdomain that
   * reports it) and the energy norms from each owned subdomain's stiffness assembled anew without
   * elimination (Σ_s over the subdomains is the stiffness of the whole body), over all ranks.
   */
  ReferenceDifference
  compare_with_reference(const MPI_Comm                             comm,
                         const std::vector<Subdomain *>            &owned,
                         const dealii::Mapping<3>                  &mapping,
                         const std::vector<dealii::Vector<double>> &u,
                         const VertexDisplacements                 &reference);

  /**
   * The displacements of the vertices @p wanted, each given as (body, body vertex, home part: the
   * lowest part of the body that holds it), from the displacements @p u of the subdomains
   * @p owned of each rank: each is asked of the rank of its home subdomain (@p owner of
   * @p first_subdomain of the body plus the part), point to point. Collective.
   */
  VertexDisplacements
  fetch_vertex_displacements(const MPI_Comm                                  comm,
                             const std::vector<unsigned int>                &first_subdomain,
                             const std::vector<unsigned int>                &owner,
                             const std::vector<Subdomain *>                 &owned,
                             const std::vector<dealii::Vector<double>>      &u,
                             const std::vector<std::array<unsigned int, 3>> &wanted);

  /**
   * Force balance of each body: the applied force Σ f (tractions and volume force), the force
   * of the supports Σ_{Γ_u} (K u − f), both summed over the subdomains and the ranks with K and
   * f assembled anew without elimination, and the contact force.
   */
  struct ForceBalance
  {
    dealii::Tensor<1, 3> applied;
    dealii::Tensor<1, 3> support;
    /** The force of the contacts on the body (given by the caller). */
    dealii::Tensor<1, 3> contact;
    /**
     * The forces that pass through the body: the sum of the absolute values of the components
     * of its nodal applied, support and contact forces. A body in the middle of a stack, whose
     * net contact force is nearly 0, passes the forces of both its contacts.
     */
    double through = 0;
    /**
     * ‖applied + support + contact‖ / #through; for a body that moves without strain (#through
     * of the size of rounding), relative to √ε Σ_{Γ_u} (|K| |u| + |f|), the accuracy its
     * support force can have.
     */
    double relative_imbalance = 0;
  };

  /** @p contact_forces: the contact forces on each body (empty: none). */
  std::vector<ForceBalance>
  compute_force_balance(const MPI_Comm                             comm,
                        const unsigned int                         n_bodies,
                        const std::vector<Subdomain *>            &owned,
                        const std::vector<dealii::Vector<double>> &u,
                        const dealii::Mapping<3>                  &mapping,
                        const std::vector<ContactForceOnBody>     &contact_forces = {});
} // namespace FetiContact
