#pragma once

#include <deal.II/fe/mapping.h>
#include <deal.II/lac/vector.h>

#include <feticontact/contact/contact_state.h>
#include <feticontact/feti/dual_problem.h>
#include <feticontact/scene/scene_parameters.h>
#include <feticontact/subdomain/subdomain.h>

#include <mpi.h>
#include <vector>

namespace FetiContact
{
  /**
   * The quantities of a solution (u, λ) that every postprocessor reads (Postprocessing::Input):
   * the largest displacement and the components that are not finite, the jump B_E u − c across
   * the interfaces, the largest principal strain, the multipliers that are not finite, and with
   * contact the contact nodes' results, the contact check and the contact forces. All over the
   * ranks.
   */
  struct SolutionEvaluation
  {
    /** max |u| over all vertices. */
    double u_max = 0;
    /** The displacement components that are not finite. */
    unsigned int u_not_finite = 0;
    /** max |B_E u − c| over the equality rows, relative to u_max (absolute if u = 0). */
    double interface_jump = 0;
    /** The largest |eigenvalue| of the cells' strains (0 if a displacement is not finite). */
    double largest_strain = 0;
    /** The largest depth of a vertex in a rigid obstacle (vertex_penetration()), not relative. */
    double vertex_penetration = 0;
    /** The entries of λ not finite. */
    unsigned int lambda_not_finite = 0;
    /** The contact nodes' results, the contact check and the contact forces. */
    ContactEvaluation contact;

    /**
     * The evaluation of the displacements @p u of this rank's subdomains @p owned and the
     * multipliers @p lambda of the dual problem @p dual (rows laid out by @p layout), with
     * @p contact holding the contact nodes (the displacements of the vertices it reads are
     * fetched from the ranks of their home subdomains: @p owner of every subdomain,
     * @p first_subdomain of every body). Collective.
     */
    static SolutionEvaluation
    of(const MPI_Comm                             comm,
       const Parameters::Scene                   &parameters,
       const std::vector<Subdomain *>            &owned,
       const std::vector<dealii::Vector<double>> &u,
       const dealii::Mapping<3>                  &mapping,
       const DualProblem                         &dual,
       const DualLayout                          &layout,
       const DualVector                          &lambda,
       const ContactState                        &contact,
       const std::vector<unsigned int>           &first_subdomain,
       const std::vector<unsigned int>           &owner);
  };
} // namespace FetiContact
