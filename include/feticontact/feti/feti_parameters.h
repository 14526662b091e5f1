#pragma once

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace FetiContact::Parameters
{
  /** `subsection FETI`: the dual problem and how it is solved. */
  struct Feti
  {
    /**
     * How Dirichlet conditions enter: `primal` eliminates them in the subdomains (the seed's way:
     * a clamped subdomain has no kernel), `total` (TFETI) writes them as rows of B_E, so every
     * subdomain floats and its kernel is the six rigid body modes.
     */
    enum class DirichletTreatment
    {
      primal,
      total
    };
    DirichletTreatment dirichlet_treatment = DirichletTreatment::total;

    /** The backend that factorizes the regularized subdomain stiffness matrices. */
    std::string local_solver = "cholmod";

    /**
     * The ranks of a node share the local work of every multiplication by F (SharedLocalWork),
     * where possible; otherwise each rank solves its own subdomains.
     */
    bool share_local_work = true;

    /** Projected CG stops when ‖P(Fλ − h)‖ ≤ tolerance · ‖P h‖ (relative). */
    double       relative_tolerance = 1e-10;
    unsigned int max_iterations     = 5000;
    /** Projected CG preconditioned by the lumped FETI preconditioner (DualProblem::apply_lumped).
     */
    bool lumped_preconditioner = true;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };
} // namespace FetiContact::Parameters
