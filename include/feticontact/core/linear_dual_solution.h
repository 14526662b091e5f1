#pragma once

#include <deal.II/base/conditional_ostream.h>

#include <feticontact/feti/dual_problem.h>
#include <feticontact/feti/feti_parameters.h>
#include <feticontact/qp/problem.h>
#include <feticontact/qp/projected_cg.h>

#include <string>

namespace FetiContact
{
  /**
   * The solution of the dual problem without contact, min ½ λᵀFλ − λᵀh subject to Gλ = e, by
   * projected CG (solve()): from the least-norm solution of Gλ = e, with the lumped
   * preconditioner if FETI/Lumped preconditioner is set, and Gλ = e restored at the end.
   */
  struct LinearDualSolution
  {
    /** λ on this rank's rows. */
    DualVector lambda;
    /** Projected CG's iterations, residual and outcome. */
    QP::SolverReport report;
    /** ‖Gλ − e‖ before Gλ = e was restored (summary.json). */
    double coarse_residual_before_restoration = 0;
    /**
     * The closing message: "converged", or why projected CG stopped (stagnation at the rounding
     * floor of F above the tolerance, or the iteration limit), with its numbers.
     */
    std::string message;

    /**
     * Solves the dual problem @p dual with the parameters @p feti, printing every 50th iteration
     * and the outcome through @p pcout. Collective.
     */
    static LinearDualSolution
    solve(DualProblem &dual, const Parameters::Feti &feti, dealii::ConditionalOStream &pcout);
  };
} // namespace FetiContact
