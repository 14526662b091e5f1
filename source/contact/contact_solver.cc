#include <feticontact/base/input_parsing.h>
#include <feticontact/contact/contact_results.h>
#include <feticontact/contact/contact_solver.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>

namespace FetiContact
{
  using namespace dealii;

  ContactSolver::ContactSolver(const DualProblem               &dual,
                               const DualLayout                &layout,
                               const std::vector<ContactNode>  &nodes,
                               const Parameters::ContactSolver &parameters,
                               std::ostream                    &out)
    : layout(layout)
    , nodes(nodes)
    , parameters(parameters)
    , out(out)
    , law(parameters.friction_law == Parameters::ContactSolver::FrictionLaw::tresca ?
            FrictionLaw::tresca(parameters.slip_bound) :
            FrictionLaw::coulomb())
    , tresca(dual, layout, nodes, parameters, out)
    , combined(tresca, parameters, [this](const DualVector &lambda) {
      return coulomb_bound(lambda);
    })
  {}

  void
  ContactSolver::set_equilibrium_test(std::function<LoadBalance(const std::vector<double> &)> test)
  {
    equilibrium_test = std::move(test);
  }

  std::vector<double>
  ContactSolver::coulomb_bound(const DualVector &lambda_tilde) const
  {
    // In the units of the forces, so that the nodes of one vertex in several zones add up
    // (slip_bounds()), then in those of each node's multipliers (forces / scale_of_node).
    std::vector<double> g = law.slip_bounds(nodes, tresca.normal_forces(lambda_tilde));
    for (unsigned int k = 0; k < nodes.size(); ++k)
      g[k] *= friction_scale / layout.scale_of_node(k);
    return g;
  }

  TrescaProblem::Monitor
  ContactSolver::monitor(Result &result)
  {
    // Algorithm 2 reports the change of the radius update inside its loop, MSA that of its last
    // step (0 in the first).
    return [this, &result](const QP::SMALBE<DualVector>::Step &step, const DualVector &lambda) {
      const bool combined_loop =
        parameters.algorithm == Parameters::ContactSolver::Algorithm::algorithm_2 &&
        law.depends_on_normal_force();
      HistoryRow row;
      row.msa_iteration      = combined_loop ? 0 : msa_iteration;
      row.smalbe_iteration   = tresca.statistics().smalbe_iterations + step.outer_iteration + 1;
      row.feasibility        = step.relative_feasibility;
      row.projected_gradient = step.relative_gradient;
      row.slip_bound_change  = combined_loop     ? combined.last_change() :
                               msa_iteration > 0 ? last_change :
                                                   0.0;
      const auto counts      = tresca.status_counts(lambda);
      row.open               = counts[0];
      row.stick              = counts[1];
      row.slip               = counts[2];
      row.inner_iterations   = step.inner_iterations;
      result.history.push_back(row);
      out << "  "
          << (row.msa_iteration > 0 ? "MSA " + std::to_string(row.msa_iteration) + ", " :
                                      std::string())
          << "SMALBE " << std::setw(3) << row.smalbe_iteration << ": ‖Gλ − e‖ " << std::scientific
          << std::setprecision(2) << row.feasibility << ", ‖g^P‖ " << row.projected_gradient
          << ", slip bound change " << row.slip_bound_change << std::defaultfloat
          << ", open/stick/slip " << row.open << '/' << row.stick << '/' << row.slip << ", inner "
          << row.inner_iterations << std::endl;
    };
  }

  void
  ContactSolver::write_history(const std::vector<HistoryRow> &rows, std::ostream &csv)
  {
    csv << "msa_iteration,smalbe_iteration,feasibility,projected_gradient,"
           "slip_bound_change,open,stick,slip,inner_iterations\n";
    for (const auto &r : rows)
      csv << r.msa_iteration << ',' << r.smalbe_iteration << ',' << r.feasibility << ','
          << r.projected_gradient << ',' << r.slip_bound_change << ',' << r.open << ',' << r.stick
          << ',' << r.slip << ',' << r.inner_iterations << '\n';
  }

  bool
  ContactSolver::slip_bounds_cannot_hold(Result &result) const
  {
    if (!equilibrium_test || layout.n_tangential == 0 ||
        parameters.algorithm == Parameters::ContactSolver::Algorithm::algorithm_2)
      return false;
    // In the units of the forces: the multipliers of a node are its forces / scale_of_node.
    // Unbounded discs (the first MSA step) hold whatever friction needs: nothing to test. Every
    // rank decides alike, since the test is collective.
    const std::vector<double> &slip_bound = tresca.slip_bounds();
    std::vector<double>        g(nodes.size());
    bool                       bounded = true;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        bounded = bounded && std::isfinite(slip_bound[k]);
        g[k]    = slip_bound[k] * layout.scale_of_node(k);
      }
    if (tresca.local_rows().max_over_ranks(bounded ? 0. : 1.) > 0)
      return false;
    const LoadBalance balance = equilibrium_test(g);
    if (balance.outcome != LoadBalance::Outcome::impossible)
      return false;
    result.no_equilibrium = true;
    result.message =
      "no equilibrium: contact forces within the slip bounds of this step (λ_N ≥ 0, "
      "‖λ_T‖ ≤ g = μ λ_N of the previous one) cannot balance the loads. On the rigid motion "
      "with " +
      balance.motion + " the loads do the work " + InputParsing::number_text(balance.load_work) +
      " J per metre of that motion, and " +
      (std::isfinite(balance.force_bound) ?
         "only contact forces whose magnitudes sum to more than " +
           InputParsing::number_text(balance.force_bound) + " N could oppose it" :
         std::string("no contact force within them can oppose it")) +
      ". For a body held only by contact: the tangential loads exceed the friction coefficient "
      "times the normal force (full sliding)";
    return true;
  }

  QP::SMALBE<DualVector>::Statistics
  ContactSolver::msa_step(Result &result, const double tolerance)
  {
    if (slip_bounds_cannot_hold(result))
      {
        QP::SMALBE<DualVector>::Statistics report;
        report.infeasible = true;
        return report;
      }
    const auto report = tresca.solve(result.lambda, result.mu, tolerance, monitor(result));
    if (report.infeasible)
      {
        result.no_equilibrium = true;
        result.message        = tresca.no_equilibrium_message(report);
      }
    return report;
  }

  ContactSolver::Result
  ContactSolver::solve()
  {
    Result result = solve_homogenized();
    tresca.recover(result.lambda, result.mu);
    const auto &counts                = tresca.statistics();
    result.smalbe_iterations          = counts.smalbe_iterations;
    result.n_bound                    = counts.n_bound;
    result.n_disc                     = counts.n_disc;
    result.cg_steps                   = counts.cg_steps;
    result.expansion_steps            = counts.expansion_steps;
    result.proportioning_steps        = counts.proportioning_steps;
    result.expansion_fallbacks        = counts.expansion_fallbacks;
    result.recursive_gradient_updates = counts.recursive_gradient_updates;
    if (parameters.algorithm == Parameters::ContactSolver::Algorithm::algorithm_2 &&
        law.depends_on_normal_force() && layout.n_tangential > 0)
      result.outer_iterations = result.smalbe_iterations;
    return result;
  }

  void
  ContactSolver::solve_one_qp(Result &result)
  {
    if (layout.n_tangential > 0)
      {
        // In the units of the node's multipliers.
        std::vector<double> g = law.slip_bounds(nodes, std::vector<double>(nodes.size(), 0.0));
        for (unsigned int k = 0; k < nodes.size(); ++k)
          if (nodes[k].friction > 0)
            g[k] /= layout.scale_of_node(k);
        tresca.set_slip_bounds(g);
      }
    const auto report       = msa_step(result, qp_tolerance);
    result.outer_iterations = 1;
    result.converged        = report.converged;
    if (!report.infeasible)
      result.message =
        report.converged ?
          "converged" :
          std::string("SMALBE did not converge") +
            (report.inner_stalled ? " (its inner solves stalled at their iteration limit)" : "");
  }

  ContactSolver::Result
  ContactSolver::solve_homogenized()
  {
    qp_tolerance = parameters.qp_tolerance;
    Result result;
    result.lambda = tresca.local_rows().vector();
    result.mu.reinit(tresca.n_equality_constraints());
    const bool coulomb = law.depends_on_normal_force() && layout.n_tangential > 0;
    if (!coulomb)
      {
        solve_one_qp(result);
        return result;
      }

    // Continuation in μ: stages μ/n, …, μ, each warm-started from the previous solution; the
    // intermediate stages need the fixed point only roughly (100 × the MSA tolerance).
    const unsigned int stages = parameters.continuation_steps;
    for (unsigned int stage = 1; stage <= stages; ++stage)
      {
        friction_scale = double(stage) / stages;
        const double msa_tolerance =
          stage < stages ? 100 * parameters.msa_tolerance : parameters.msa_tolerance;
        if (stages > 1)
          out << "Friction continuation: stage " << stage << " of " << stages << ", μ × "
              << friction_scale << std::endl;
        if (parameters.algorithm == Parameters::ContactSolver::Algorithm::algorithm_2)
          {
            const auto outcome =
              combined.run(result.lambda, result.mu, msa_tolerance, monitor(result));
            result.converged      = outcome.converged;
            result.no_equilibrium = outcome.no_equilibrium;
            result.message        = outcome.message;
          }
        else
          solve_msa(result, msa_tolerance, stage == 1);
        if (!result.converged)
          {
            if (stages > 1)
              result.message += " (friction continuation stage " + std::to_string(stage) + " of " +
                                std::to_string(stages) + ")";
            return result;
          }
      }
    return result;
  }

  void
  ContactSolver::solve_msa(Result &result, const double msa_tolerance, const bool cold_start)
  {
    // MSA: a cold start begins with unbounded tangential multipliers (the contact sticks:
    // g = ∞, a problem that has a solution whenever the normal contact holds the bodies; g = 0,
    // the frictionless problem, has none for a body held by friction), a warm one (a later stage
    // of the continuation in μ) with g = μ λ_N of the current λ; then
    // g ← (1 − ω) g + ω μ λ_N (the first update takes ω = 1).
    result.converged = false;
    std::vector<double> g =
      cold_start ? std::vector<double>(nodes.size(), std::numeric_limits<double>::infinity()) :
                   coulomb_bound(result.lambda);
    tresca.set_slip_bounds(g);
    // Inexact MSA: step j solves the Tresca problem to max(ε_QP, c · change_{j−1}) (change_0 = 1):
    // the slip bound of the early steps is far from the fixed point, and solving for it to the
    // final precision buys nothing. MSA stops only after a step solved to ε_QP.
    double             previous_change = 1;
    const unsigned int first           = result.outer_iterations;
    // The last completed step: its result, its slip bounds, its relaxation, its precision.
    // A slip bound from an inexact step may be too small to hold a body held by friction (its
    // λ_N is rough); SMALBE then proves the next Tresca problem infeasible, and before that is
    // reported as "no equilibrium" the step is solved again to the final precision.
    struct Step
    {
      DualVector          lambda;
      Vector<double>      mu;
      std::vector<double> g;
      double              omega = 1;
      bool                final = true;
    };
    std::optional<Step> previous;
    const auto          relax = [&](const std::vector<double> &g_old, const double omega) {
      const auto          target = coulomb_bound(result.lambda);
      std::vector<double> next(g_old.size());
      for (unsigned int k = 0; k < nodes.size(); ++k)
        next[k] = std::isfinite(g_old[k]) ? (1 - omega) * g_old[k] + omega * target[k] : target[k];
      return next;
    };
    for (msa_iteration = first + 1; msa_iteration <= first + parameters.max_msa_iterations;
         ++msa_iteration)
      {
        qp_tolerance =
          std::max(parameters.qp_tolerance, parameters.inexact_msa_factor * previous_change);
        const bool final_precision = qp_tolerance <= parameters.qp_tolerance;
        const auto report          = msa_step(result, qp_tolerance);
        if (report.infeasible && previous && !previous->final)
          {
            out << "MSA iteration " << msa_iteration
                << ": no equilibrium within the slip bounds of the inexact step "
                << msa_iteration - 1 << "; that step solved again to " << parameters.qp_tolerance
                << std::endl;
            result.no_equilibrium = false;
            result.message.clear();
            result.lambda = previous->lambda;
            result.mu     = previous->mu;
            tresca.set_slip_bounds(previous->g);
            qp_tolerance       = parameters.qp_tolerance;
            const auto again   = msa_step(result, qp_tolerance);
            const bool settled = again.converged && !again.infeasible;
            if (!settled)
              {
                result.outer_iterations = msa_iteration;
                if (!again.infeasible)
                  result.message =
                    "SMALBE did not converge in MSA iteration " + std::to_string(msa_iteration - 1);
                else
                  result.message += " (MSA iteration " + std::to_string(msa_iteration - 1) +
                                    " solved again to the final precision)";
                return;
              }
            g                = relax(previous->g, previous->omega);
            last_change      = tresca.relative_change(previous->g, g);
            previous_change  = last_change;
            previous->final  = true;
            previous->lambda = result.lambda;
            previous->mu     = result.mu;
            tresca.set_slip_bounds(g);
            --msa_iteration;
            continue;
          }
        if (report.infeasible)
          {
            result.outer_iterations = msa_iteration;
            result.message +=
              " (MSA iteration " + std::to_string(msa_iteration) +
              (msa_iteration == first + 1 ? ")" :
                                            ", slip bounds g = μ λ_N of the previous iteration)");
            return;
          }
        const double omega       = msa_iteration == first + 1 ? 1.0 : parameters.relaxation;
        previous                 = Step{result.lambda, result.mu, g, omega, final_precision};
        std::vector<double> next = relax(g, omega);
        last_change              = tresca.relative_change(g, next);
        g.swap(next);
        previous_change         = last_change;
        result.outer_iterations = msa_iteration;
        out << "MSA iteration " << msa_iteration << ": relative change of the slip bound "
            << last_change << ", SMALBE " << (report.converged ? "converged" : "NOT converged")
            << " to " << qp_tolerance << " in " << report.iterations << " iterations" << std::endl;
        if (!report.converged)
          {
            result.message =
              "SMALBE did not converge in MSA iteration " + std::to_string(msa_iteration) +
              (report.inner_stalled ? " (its inner solves stalled at their iteration limit)" : "");
            return;
          }
        if (last_change <= msa_tolerance && final_precision)
          {
            result.converged = true;
            result.message   = "converged";
            return;
          }
        tresca.set_slip_bounds(g);
      }
    result.message = "MSA did not converge in " + std::to_string(parameters.max_msa_iterations) +
                     " iterations; last relative change of the slip bound " +
                     InputParsing::number_text(last_change);
  }

} // namespace FetiContact
