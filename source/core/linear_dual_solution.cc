#include <feticontact/base/input_parsing.h>
#include <feticontact/core/linear_dual_solution.h>
#include <feticontact/feti/local_dual_rows.h>

#include <iomanip>

namespace FetiContact
{
  namespace
  {
    /** The closing message of projected CG's @p report with the parameters @p feti. */
    std::string
    closing_message(const QP::SolverReport &report, const Parameters::Feti &feti)
    {
      const double tolerance = feti.projected_cg.tolerance;
      if (report.converged)
        return "converged";
      if (report.stagnated)
        return "projected CG stagnated after " + std::to_string(report.iterations) +
               " iterations at the relative projected gradient " +
               InputParsing::number_text(report.relative_residual) +
               " (recomputed from λ), above " +
               "FETI/Relative tolerance = " + InputParsing::number_text(tolerance) +
               ": its least value did not halve over the last quarter of the iterations, so the "
               "rounding of F = B K⁺ Bᵀ bounds the attainable accuracy (ill-conditioned subdomain "
               "matrices, e.g. a thin plate); a tolerance at or above that value is attainable";
      return "projected CG did not converge in FETI/Maximum iterations = " +
             std::to_string(feti.projected_cg.max_iterations) +
             " iterations (relative projected gradient " +
             InputParsing::number_text(report.relative_residual) + ", tolerance " +
             InputParsing::number_text(tolerance) + ")";
    }
  } // namespace

  LinearDualSolution
  LinearDualSolution::solve(DualProblem                &dual,
                            const Parameters::Feti     &feti,
                            dealii::ConditionalOStream &pcout)
  {
    LinearDualSolution  solution;
    const LocalDualRows rows(dual);
    DualVector          lambda = rows.vector();
    dual.coarse.least_norm_solution(dual.e, lambda);
    solution.report =
      QP::ProjectedCG<DualVector>(feti.projected_cg)
        .solve([&dual](const DualVector &x, DualVector &y) { dual.apply_F(x, y); },
               [&dual](DualVector &x) { dual.coarse.project(x); },
               rows.h(),
               lambda,
               [&pcout](unsigned int it, double residual) {
                 if (it % 50 == 0)
                   pcout << "  PCG iteration " << std::setw(5) << it
                         << "   ‖P(Fλ − h)‖ / ‖Ph‖ = " << std::scientific << std::setprecision(3)
                         << residual << std::defaultfloat << std::endl;
               },
               feti.lumped_preconditioner ?
                 QP::Operator<DualVector>(
                   [&dual](const DualVector &x, DualVector &y) { dual.apply_lumped(x, y); }) :
                 QP::Operator<DualVector>());
    solution.coarse_residual_before_restoration = dual.coarse.restore_feasibility(lambda, dual.e);
    solution.lambda                             = std::move(lambda);
    const QP::SolverReport &report              = solution.report;
    pcout << "Projected CG: " << (report.converged ? "converged" : "NOT converged") << " after "
          << report.iterations << " iterations, relative projected gradient " << std::scientific
          << std::setprecision(3) << report.relative_residual << std::defaultfloat << std::endl;
    solution.message = closing_message(report, feti);
    return solution;
  }
} // namespace FetiContact
