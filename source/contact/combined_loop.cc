#include <feticontact/base/input_parsing.h>
#include <feticontact/contact/combined_loop.h>

namespace FetiContact
{
  using namespace dealii;

  CombinedLoop::CombinedLoop(TrescaProblem                                         &tresca,
                             const Parameters::ContactSolver                       &parameters,
                             std::function<std::vector<double>(const DualVector &)> slip_bound_of)
    : tresca(tresca)
    , parameters(parameters)
    , slip_bound_of(std::move(slip_bound_of))
  {
    moving_set.update    = [this](const DualVector &lambda) { update_radii(lambda); };
    moving_set.unchanged = [this]() { return change <= this->parameters.msa_tolerance; };
    // At the start λ_N = 0 and g = 0 do not change either: final only after a few updates.
    moving_set.final = [this]() {
      return radius_updates >= 3 && change <= this->parameters.msa_tolerance;
    };
  }

  double
  CombinedLoop::last_change() const
  {
    return change;
  }

  void
  CombinedLoop::update_radii(const DualVector &lambda)
  {
    const auto                 target = slip_bound_of(lambda);
    const std::vector<double> &g_old  = tresca.slip_bounds();
    std::vector<double>        g(g_old.size());
    for (unsigned int k = 0; k < g.size(); ++k)
      g[k] = (1 - parameters.relaxation) * g_old[k] + parameters.relaxation * target[k];
    change = tresca.relative_change(g_old, g);
    ++radius_updates;
    tresca.set_slip_bounds(g);
  }

  CombinedLoop::Outcome
  CombinedLoop::run(DualVector                   &lambda,
                    Vector<double>               &nu,
                    const double                  msa_tolerance,
                    const TrescaProblem::Monitor &monitor)
  {
    Outcome outcome;
    for (unsigned int call = 0; call < parameters.max_msa_iterations; ++call)
      {
        const auto report = tresca.solve(lambda, nu, parameters.qp_tolerance, monitor, &moving_set);
        if (report.infeasible)
          {
            outcome.no_equilibrium = true;
            outcome.message        = tresca.no_equilibrium_message(report);
            return outcome;
          }
        const auto target = slip_bound_of(lambda);
        change            = tresca.relative_change(tresca.slip_bounds(), target);
        if (report.converged && change <= msa_tolerance)
          {
            outcome.converged = true;
            outcome.message   = "converged";
            return outcome;
          }
        tresca.set_slip_bounds(target);
      }
    outcome.message = "Algorithm 2 did not converge; last relative change of the slip bound " +
                      InputParsing::number_text(change);
    return outcome;
  }

} // namespace FetiContact
