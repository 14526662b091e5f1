#pragma once

#include <deal.II/base/parameter_handler.h>

#include <feticontact/qp/projected_cg.h>

#include <string>

namespace FetiContact::Parameters
{
  /** `subsection FETI`: the dual problem and how it is solved. */
  struct Feti
  {
    /**
     * How Dirichlet conditions enter: `primal` eliminates them in the subdomains (the paper's way:
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
     * How the contact rows N, T1, T2 take a contact node that lies on a subdomain interface
     * (p ≥ 2 glued copies): `lowest copy` puts the row on the copy of the lowest-numbered
     * subdomain; `average` puts it on the mean of all copies, scaled so that the row keeps its
     * length. The averaged row is orthogonal to the gluing rows there (Helmert's contrasts sum
     * to zero), so on a rigid obstacle B has orthonormal rows: Dostál's setting for the bounds
     * on the spectrum of F (a row between two bodies has the length √2 either way).
     * Not the default: on the brick it saves applications of F on small meshes and costs some
     * on large ones (doc/performance.md, "Numerical scalability").
     */
    bool average_contact_rows = false;

    /**
     * Where the factor of the coarse matrix GGᵀ lives (CoarseProblem::FactorStorage): `per node`,
     * the first rank of each node's ranks assembles and factorizes GGᵀ and the node's ranks
     * solve with the one factor in shared memory; `per rank`, every rank has its own. The
     * solves give the same numbers either way.
     */
    enum class CoarseFactor
    {
      per_node,
      per_rank
    };
    CoarseFactor coarse_factor = CoarseFactor::per_node;

    /** Projected CG of problems without contact (its tolerance and iteration limit). */
    QP::ProjectedCGParameters projected_cg;
    /** Projected CG preconditioned by the lumped FETI preconditioner (DualProblem::apply_lumped).
     */
    bool lumped_preconditioner = true;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };
} // namespace FetiContact::Parameters
