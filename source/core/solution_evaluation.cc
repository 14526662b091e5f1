#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_tools.h>

#include <feticontact/core/solution_evaluation.h>
#include <feticontact/postprocessing/stresses.h>
#include <feticontact/postprocessing/verification.h>

#include <algorithm>
#include <cmath>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    /**
     * u_max, u_not_finite and (with contact) the vertex penetration of @p evaluation: every
     * vertex once, in the subdomain that reports it.
     */
    void
    evaluate_displacements(SolutionEvaluation                        &evaluation,
                           const std::vector<Subdomain *>            &owned,
                           const std::vector<dealii::Vector<double>> &u,
                           const Parameters::Contact                 &contact,
                           const bool                                 with_contact,
                           const MPI_Comm                             comm)
    {
      for (unsigned int i = 0; i < owned.size(); ++i)
        for (const auto &[w, v] : owned[i]->reported_vertices())
          {
            Tensor<1, 3> u_v;
            for (unsigned int c = 0; c < 3; ++c)
              {
                u_v[c] = u[i][owned[i]->vertex_dofs[v][c]];
                evaluation.u_not_finite += !std::isfinite(u_v[c]);
              }
            evaluation.u_max = std::max(evaluation.u_max, u_v.norm());
            if (with_contact)
              evaluation.vertex_penetration =
                std::max(evaluation.vertex_penetration,
                         vertex_penetration(
                           contact, owned[i]->body.index, owned[i]->mesh.get_vertices()[v], u_v));
          }
      evaluation.u_max              = Utilities::MPI::max(evaluation.u_max, comm);
      evaluation.u_not_finite       = Utilities::MPI::sum(evaluation.u_not_finite, comm);
      evaluation.vertex_penetration = Utilities::MPI::max(evaluation.vertex_penetration, comm);
    }

    /** max |B_E u − c| over the equality rows of @p layout, over all ranks. */
    double
    largest_equality_residual(const DualProblem                         &dual,
                              const DualLayout                          &layout,
                              const std::vector<dealii::Vector<double>> &u,
                              const MPI_Comm                             comm)
    {
      double jump = 0;
      for_each_held_row(dual.constraint_residual(u),
                        [&](const unsigned int row, const double residual) {
                          if (row >= layout.first_equality())
                            jump = std::max(jump, std::abs(residual));
                        });
      return Utilities::MPI::max(jump, comm);
    }

    /** The number of entries of @p lambda that are not finite numbers, over all ranks. */
    unsigned int
    multipliers_not_finite(const DualVector &lambda, const MPI_Comm comm)
    {
      unsigned int n = 0;
      for_each_held_row(lambda,
                        [&](const unsigned int, const double l) { n += !std::isfinite(l); });
      return Utilities::MPI::sum(n, comm);
    }

    /** The largest |eigenvalue| of the strains of the cells of @p owned, over all ranks. */
    double
    largest_principal_strain(const std::vector<Subdomain *>            &owned,
                             const std::vector<dealii::Vector<double>> &u,
                             const dealii::Mapping<3>                  &mapping,
                             const bool                                 u_finite,
                             const MPI_Comm                             comm)
    {
      double largest = 0;
      if (u_finite)
        for (unsigned int i = 0; i < owned.size(); ++i)
          for (const auto &strain : cell_strains(*owned[i], mapping, u[i]))
            for (const double e : eigenvalues(strain))
              largest = std::max(largest, std::abs(e));
      return Utilities::MPI::max(largest, comm);
    }

    /** The largest cell diameter of the subdomains of all ranks. */
    double
    largest_cell(const std::vector<Subdomain *> &owned, const MPI_Comm comm)
    {
      double largest = 0;
      for (const Subdomain *s : owned)
        largest = std::max(largest, GridTools::maximal_cell_diameter(s->mesh));
      return Utilities::MPI::max(largest, comm);
    }
  } // namespace

  SolutionEvaluation
  SolutionEvaluation::of(const MPI_Comm                             comm,
                         const Parameters::Scene                   &parameters,
                         const std::vector<Subdomain *>            &owned,
                         const std::vector<dealii::Vector<double>> &u,
                         const dealii::Mapping<3>                  &mapping,
                         const DualProblem                         &dual,
                         const DualLayout                          &layout,
                         const DualVector                          &lambda,
                         const ContactState                        &contact,
                         const std::vector<unsigned int>           &first_subdomain,
                         const std::vector<unsigned int>           &owner)
  {
    SolutionEvaluation evaluation;
    const bool         with_contact = contact.n_nodes() > 0;
    evaluate_displacements(evaluation, owned, u, parameters.contact, with_contact, comm);
    // Constraint residual B_E u − c: the jump of the displacements across interfaces (and the
    // Dirichlet misfit in TFETI), relative to the largest displacement. Only the equality rows:
    // the contact rows of B u − c are the gaps and the slips.
    const double jump            = largest_equality_residual(dual, layout, u, comm);
    evaluation.lambda_not_finite = multipliers_not_finite(lambda, comm);
    evaluation.interface_jump    = evaluation.u_max > 0 ? jump / evaluation.u_max : jump;
    evaluation.largest_strain =
      largest_principal_strain(owned, u, mapping, evaluation.u_not_finite == 0, comm);
    const unsigned int n_bodies = parameters.bodies.size();
    evaluation.contact.forces.on_body.resize(n_bodies);
    evaluation.contact.forces.of_zone.resize(parameters.contact.zones.size());
    if (!with_contact)
      return evaluation;
    const bool tresca =
      parameters.contact_solver.friction_law == Parameters::ContactSolver::FrictionLaw::tresca;
    const VertexDisplacements surface_u =
      fetch_vertex_displacements(comm, first_subdomain, owner, owned, u, contact.vertices_read());
    evaluation.contact =
      contact.evaluate(lambda,
                       surface_u,
                       evaluation.u_max,
                       evaluation.vertex_penetration,
                       largest_cell(owned, comm),
                       parameters.contact,
                       tresca ? std::optional<double>(parameters.contact_solver.slip_bound) :
                                std::nullopt,
                       n_bodies,
                       comm);
    return evaluation;
  }
} // namespace FetiContact
