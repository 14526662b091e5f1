#include <feticontact/base/input_parsing.h>
#include <feticontact/contact/contact_solver.h>
#include <feticontact/qp/smalbe.h>
#include <feticontact/qp/transforms.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    /**
     * ‖next − previous‖ / ‖next‖ of two slip bounds (an infinite previous entry, the first MSA
     * step's unbounded discs, counts as 0); 0 if next = 0.
     */
    double
    relative_change(const std::vector<double> &previous, const std::vector<double> &next)
    {
      double d2 = 0, n2 = 0;
      for (unsigned int k = 0; k < next.size(); ++k)
        {
          const double d = std::isfinite(previous[k]) ? next[k] - previous[k] : next[k];
          d2 += d * d;
          n2 += next[k] * next[k];
        }
      return n2 > 0 ? std::sqrt(d2 / n2) : 0.0;
    }
  } // namespace

  ContactSolver::ContactSolver(const DualProblem               &dual,
                               const DualLayout                &layout,
                               const std::vector<ContactNode>  &nodes,
                               const Parameters::ContactSolver &parameters,
                               std::ostream                    &out,
                               std::ostream                    *history)
    : dual(dual)
    , layout(layout)
    , nodes(nodes)
    , parameters(parameters)
    , out(out)
    , history(history)
    , set(layout.size())
    , set_c(layout.size() - layout.n_tangential)
    , set_t(layout.n_tangential)
    , disc_of_node(nodes.size(), numbers::invalid_unsigned_int)
    , slip_bound(nodes.size(), 0.0)
  {
    if (history != nullptr)
      {
        *history << "msa_iteration,smalbe_iteration,feasibility,projected_gradient,"
                    "slip_bound_change,open,stick,slip,inner_iterations\n";
      }
    // Homogenization for the projector variant: Gλ₀ = e, h − Fλ₀, ẽ − G̃λ₀ = 0. λ₀ is taken
    // from the gluing and Dirichlet rows alone when they restrain the floating subdomains, else
    // from those and the normal rows, and only else from all rows (CoarseProblem::
    // particular_solution): the bounds are then λ̃_N ≥ 0 and the discs centred at the origin,
    // where radii far below ‖λ₀‖ (F = 1e-8, nodes without contact) are resolved.
    row_tier.assign(layout.size(), 0);
    for (unsigned int r = 0; r < layout.first_equality(); ++r)
      row_tier[r] = r < layout.first_normal() ? 2 : 1;
    original.hessian = [this](const Vector<double> &x, Vector<double> &y) {
      this->dual.apply_F(x, y);
    };
    original.linear_term = dual.h;
    original.set         = &set;
    original.G           = [this](const Vector<double> &x, Vector<double> &y) {
      this->dual.coarse.apply_G_orthonormal(x, y);
    };
    original.Gt = [this](const Vector<double> &x, Vector<double> &y) {
      this->dual.coarse.apply_Gt_orthonormal(x, y);
    };
    original.e = dual.coarse.orthonormal_rhs(dual.e);
    problem    = original;
    lambda0.reinit(layout.size());
    projector =
      parameters.equality_constraint == Parameters::ContactSolver::EqualityConstraint::projector &&
      dual.coarse.n_modes() > 0;
    if (projector)
      {
        homogenization.emplace(original, dual.coarse.particular_solution(dual.e, row_tier));
        lambda0     = homogenization->particular_solution();
        homogeneous = homogenization->transformed(set);
        projector_enforcement.emplace(homogeneous);
        problem = projector_enforcement->transformed();
      }

    const unsigned int n_T = layout.n_tangential;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        const unsigned int r = layout.normal_row[k];
        set.set_lower_bound(r, -lambda0[r]);
        set_c.set_lower_bound(r - n_T, -lambda0[r]);
        const unsigned int t = layout.tangential_row[k];
        if (t == numbers::invalid_unsigned_int)
          continue;
        if (!layout.polygonal)
          {
            const std::array<double, 2> centre{{-lambda0[t], -lambda0[t + 1]}};
            disc_of_node[k] = set.add_disc(t, t + 1, centre, 0.0);
            set_t.add_disc(t, t + 1, centre, 0.0);
          }
      }
    set_slip_bounds(slip_bound);
    // The equality constraint is used in the orthonormalized form G̃λ = ẽ (G̃G̃ᵀ = I), so ‖G̃‖ = 1.
    G_norm = dual.coarse.n_modes() > 0 ? 1.0 : 0.0;
    // The FETI part of the Hessian: F, or PFP in the projector variant. ‖F‖ bounds ‖PFP‖, but
    // with floating subdomains it also measures the local pseudo-inverses on the rigid body
    // modes, which P removes (Penalty norm = projected F estimates ‖PFP‖ itself, and then ‖F‖
    // is not needed: SMALBE gets ‖PFP‖, the norm of the FETI part of the Hessian it applies,
    // and the ten multiplications of the power method for ‖F‖ are saved).
    if (parameters.penalty_projected_norm && projector)
      {
        Vector<double> Pv;
        feti_norm = 1.05 * QP::estimate_norm(
                             [&](const Vector<double> &x, Vector<double> &y) {
                               Pv = x;
                               apply_P(Pv);
                               dual.apply_F(Pv, y);
                               apply_P(y);
                             },
                             layout.size(),
                             projected_norm_iterations);
      }
    else
      feti_norm = 1.05 * QP::estimate_norm([&](const Vector<double> &x,
                                               Vector<double>       &y) { dual.apply_F(x, y); },
                                           layout.size(),
                                           10);
    rho = G_norm > 0 ? parameters.penalty_factor * feti_norm / (G_norm * G_norm) : feti_norm;
    // ‖F + ρG̃ᵀG̃‖ ≤ ‖F‖ + ρ. In the projector variant the Hessian PFP + ρQ (Q = G̃ᵀG̃ = I − P) is
    // block diagonal in ker G̃ ⊕ range G̃ᵀ, so its norm is max(‖PFP‖, ρ) ≤ max(‖F‖, ρ).
    hessian_norm = parameters.hessian_norm_max && projector ?
                     std::max(feti_norm, rho * G_norm * G_norm) :
                     feti_norm + rho * G_norm * G_norm;
    if (parameters.penalty_projected_norm && projector)
      out << "  Penalty: ρ = " << std::scientific << std::setprecision(3) << rho << " ("
          << parameters.penalty_factor << " ‖PFP‖; ‖PFP‖ ≈ " << feti_norm << ")"
          << std::defaultfloat << std::endl;
    if (parameters.arc_scale_mean_diagonal)
      {
        // tr(A)/m for A = PFP + ρQ (projector) or F + ρG̃ᵀG̃ (penalty): Hutchinson's estimate of
        // tr(PFP) = E[(Pv)ᵀF(Pv)] or tr(F), and exactly tr(ρG̃ᵀG̃) = ρ tr(G̃G̃ᵀ) = ρ × the
        // number of rigid modes (G̃ has orthonormal rows).
        const unsigned int m = layout.size();
        Vector<double>     Pv;
        const auto         PFP = [&](const Vector<double> &v, Vector<double> &y) {
          Pv = v;
          if (projector)
            apply_P(Pv);
          dual.apply_F(Pv, y);
        };
        arc_scale = QP::estimate_mean_diagonal(PFP, m, arc_scale_probes) +
                    rho * G_norm * G_norm * dual.coarse.n_modes() / m;
        out << "  Arc preconditioner scale: mean diagonal of the Hessian " << std::scientific
            << std::setprecision(3) << arc_scale << " (" << arc_scale_probes
            << " probes), its norm bound " << hessian_norm << std::defaultfloat << std::endl;
      }
  }

  void
  ContactSolver::apply_P(Vector<double> &v) const
  {
    Vector<double> Gv, Qv;
    dual.coarse.apply_G_orthonormal(v, Gv);
    dual.coarse.apply_Gt_orthonormal(Gv, Qv);
    v -= Qv;
  }

  Vector<double>
  ContactSolver::total(const Vector<double> &lambda_tilde) const
  {
    Vector<double> lambda(lambda_tilde);
    lambda += lambda0;
    return lambda;
  }

  std::vector<double>
  ContactSolver::coulomb_bound(const Vector<double> &lambda_tilde) const
  {
    // In the units of the forces (a node's multipliers are its forces / scale_of_node), so that
    // the nodes of one vertex in several zones add up (slip_bounds()).
    std::vector<double> normal_force(nodes.size());
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        const unsigned int r = layout.normal_row[k];
        normal_force[k]      = layout.scale_of_node(k) * (lambda_tilde[r] + lambda0[r]);
      }
    std::vector<double> g = slip_bounds(nodes, normal_force);
    for (unsigned int k = 0; k < nodes.size(); ++k)
      g[k] *= friction_scale / layout.scale_of_node(k);
    return g;
  }

  void
  ContactSolver::set_slip_bounds(const std::vector<double> &g)
  {
    slip_bound                = g;
    const unsigned int s      = layout.tangential_per_node;
    const double       shrink = std::sin(numbers::PI / (2.0 * s));
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        const unsigned int t = layout.tangential_row[k];
        if (t == numbers::invalid_unsigned_int)
          continue;
        if (layout.polygonal)
          for (unsigned int j = 0; j < s; ++j)
            {
              const double c = lambda0[t + j];
              set.set_interval(t + j, -shrink * g[k] - c, shrink * g[k] - c);
              set_t.set_interval(t + j, -shrink * g[k] - c, shrink * g[k] - c);
            }
        else
          {
            set.set_disc_radius(disc_of_node[k], g[k]);
            set_t.set_disc_radius(disc_of_node[k], g[k]);
          }
      }
  }

  QP::SolverReport
  ContactSolver::gauss_seidel(const QP::Operator   &A,
                              const Vector<double> &b,
                              Vector<double>       &lambda,
                              const double          tolerance,
                              const bool            update_radii,
                              Result               &result)
  {
    const unsigned int m = lambda.size(), n_T = layout.n_tangential, n_c = m - n_T;
    Vector<double>     full(m), Afull(m);
    // A restricted to a block: pad with zeros, multiply, extract.
    const auto block_operator =
      [&](const unsigned int first, const unsigned int n, unsigned int &counter) {
        return [&, first, n](const Vector<double> &x, Vector<double> &y) {
          full = 0;
          for (unsigned int i = 0; i < n; ++i)
            full[first + i] = x[i];
          A(full, Afull);
          ++counter;
          y.reinit(n);
          for (unsigned int i = 0; i < n; ++i)
            y[i] = Afull[first + i];
        };
      };
    // b_block − A_{block, other} λ_other.
    const auto block_rhs =
      [&](const unsigned int first, const unsigned int n, unsigned int &counter) {
        Vector<double> rhs(n);
        full = lambda;
        for (unsigned int i = 0; i < n; ++i)
          full[first + i] = 0;
        if (full.l2_norm() > 0)
          {
            A(full, Afull);
            ++counter;
          }
        else
          Afull = 0;
        for (unsigned int i = 0; i < n; ++i)
          rhs[i] = b[first + i] - Afull[first + i];
        return rhs;
      };

    QP::SolverReport report;
    report.converged                 = true;
    QP::MPGP::AdditionalData options = mpgp_options();
    // Each block to tolerance/2: when a sweep changes nothing, both block gradients are then
    // below it and ‖(g^P_c, g^P_t)‖ ≤ tolerance/√2; with `tolerance` itself per block the sweeps
    // could stall with the combined norm between tolerance and √2 tolerance.
    options.tolerance = tolerance / 2;
    for (unsigned int sweep = 0; sweep < parameters.gauss_seidel_sweeps; ++sweep)
      {
        // λ_c = [λ_N; λ_E] by MPRGP with λ_T fixed.
        {
          Vector<double> x(n_c);
          for (unsigned int i = 0; i < n_c; ++i)
            x[i] = lambda[n_T + i];
          const Vector<double> rhs = block_rhs(n_T, n_c, result.n_bound);
          const auto           r =
            QP::MPGP(options).solve(block_operator(n_T, n_c, result.n_bound), rhs, set_c, x);
          for (unsigned int i = 0; i < n_c; ++i)
            lambda[n_T + i] = x[i];
          report.iterations += r.iterations;
          report.converged &= r.converged;
          result.count_steps(r);
        }
        if (n_T == 0)
          break;
        if (update_radii)
          {
            const auto          target = coulomb_bound(lambda);
            std::vector<double> g(nodes.size());
            for (unsigned int k = 0; k < nodes.size(); ++k)
              g[k] =
                (1 - parameters.relaxation) * slip_bound[k] + parameters.relaxation * target[k];
            last_change = relative_change(slip_bound, g);
            ++radius_updates;
            set_slip_bounds(g);
          }
        // λ_T by KPG (MPGP on the discs) with λ_c fixed.
        {
          Vector<double> x(n_T);
          for (unsigned int i = 0; i < n_T; ++i)
            x[i] = lambda[i];
          const Vector<double> rhs = block_rhs(0, n_T, result.n_disc);
          const auto           r =
            QP::MPGP(options).solve(block_operator(0, n_T, result.n_disc), rhs, set_t, x);
          for (unsigned int i = 0; i < n_T; ++i)
            lambda[i] = x[i];
          report.iterations += r.iterations;
          report.converged &= r.converged;
          result.count_steps(r);
        }
      }
    return report;
  }

  void
  ContactSolver::history_row(const unsigned int    msa,
                             const unsigned int    smalbe,
                             const double          feasibility,
                             const double          gradient,
                             const double          change,
                             const Vector<double> &lambda_tilde,
                             const unsigned int    inner)
  {
    const Vector<double> lambda = total(lambda_tilde);
    unsigned int         n_open = 0, n_stick = 0, n_slip = 0;
    // A node is open when its normal force σ_k λ_N (σ_k ≠ 1 only with averaged contact rows)
    // is below 1e-8 of the largest; slip and stick compare multipliers of the same node.
    double lambda_max = 0;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      lambda_max = std::max(lambda_max, layout.scale_of_node(k) * lambda[layout.normal_row[k]]);
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        const double       lN = layout.scale_of_node(k) * lambda[layout.normal_row[k]];
        const unsigned int t  = layout.tangential_row[k];
        double             lT = 0;
        if (t != numbers::invalid_unsigned_int)
          for (unsigned int j = 0; j < layout.tangential_per_node; ++j)
            lT += lambda[t + j] * lambda[t + j];
        lT = std::sqrt(lT);
        if (lN <= 1e-8 * lambda_max)
          ++n_open;
        else if (t == numbers::invalid_unsigned_int || lT >= (1 - 1e-4) * slip_bound[k])
          ++n_slip;
        else
          ++n_stick;
      }
    if (history)
      *history << msa << ',' << smalbe << ',' << feasibility << ',' << gradient << ',' << change
               << ',' << n_open << ',' << n_stick << ',' << n_slip << ',' << inner << '\n';
    out << "  " << (msa > 0 ? "MSA " + std::to_string(msa) + ", " : std::string()) << "SMALBE "
        << std::setw(3) << smalbe << ": ‖Gλ − e‖ " << std::scientific << std::setprecision(2)
        << feasibility << ", ‖g^P‖ " << gradient << ", slip bound change " << change
        << std::defaultfloat << ", open/stick/slip " << n_open << '/' << n_stick << '/' << n_slip
        << ", inner " << inner << std::endl;
  }

  QP::MPGP::AdditionalData
  ContactSolver::mpgp_options() const
  {
    QP::MPGP::AdditionalData options;
    options.max_iterations               = parameters.max_inner_iterations;
    options.step                         = 1.9 / hessian_norm;
    options.disc_rotations               = parameters.disc_rotations;
    options.expansion                    = parameters.expansion;
    options.recursive_gradient_tolerance = parameters.recursive_gradient_tolerance;
    options.arc_scale                    = arc_scale;
    return options;
  }

  void
  ContactSolver::set_equilibrium_test(std::function<LoadBalance(const std::vector<double> &)> test)
  {
    equilibrium_test = std::move(test);
  }

  bool
  ContactSolver::slip_bounds_cannot_hold(Result &result) const
  {
    if (!equilibrium_test || layout.n_tangential == 0 ||
        parameters.algorithm == Parameters::ContactSolver::Algorithm::algorithm_2)
      return false;
    // In the units of the forces: the multipliers of a node are its forces / scale_of_node.
    std::vector<double> g(nodes.size());
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        if (!std::isfinite(slip_bound[k]))
          return false;
        g[k] = slip_bound[k] * layout.scale_of_node(k);
      }
    const LoadBalance balance = equilibrium_test(g);
    if (balance.outcome != LoadBalance::Outcome::impossible)
      return false;
    result.no_equilibrium = true;
    result.message =
      "no equilibrium: contact forces within the slip bounds of this step (λ_N ≥ 0, "
      "‖λ_T‖ ≤ g = F λ_N of the previous one) cannot balance the loads. On the rigid motion "
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

  QP::SMALBE::Statistics
  ContactSolver::solve_tresca(Vector<double> &lambda, Vector<double> &mu, Result &result)
  {
    if (slip_bounds_cannot_hold(result))
      {
        QP::SMALBE::Statistics report;
        report.infeasible = true;
        return report;
      }
    const auto algorithm = parameters.algorithm;
    using A              = Parameters::ContactSolver::Algorithm;
    QP::SMALBE::AdditionalData options;
    options.tolerance             = qp_tolerance;
    options.feasibility_tolerance = qp_tolerance;
    options.max_outer_iterations  = parameters.max_smalbe_iterations;
    options.rho                   = rho;
    options.F_norm                = feti_norm;
    options.G_norm                = G_norm;
    options.inner                 = mpgp_options();
    options.inner_floor           = parameters.inner_tolerance_floor;
    options.multiplier_step       = parameters.multiplier_step;
    const bool split              = algorithm == A::algorithm_1 || algorithm == A::algorithm_2;
    const bool combined           = algorithm == A::algorithm_2;
    if (combined)
      options.max_inner_calls = 1;
    QP::SMALBE smalbe(options);
    if (split && layout.n_tangential > 0)
      smalbe.set_inner_solver([&](const QP::Operator   &op,
                                  const Vector<double> &b,
                                  Vector<double>       &x,
                                  const double          tolerance,
                                  const Vector<double> & /*gradient*/) {
        QP::SMALBE::InnerReport r = gauss_seidel(op, b, x, tolerance, combined, result);
        if (combined)
          {
            // The radii move inside the loop: M is adapted only once they have settled, and
            // they are final once they have settled after λ_N has been computed a few times
            // (at the start λ_N = 0 and g = 0 do not change either).
            r.same_set  = last_change <= parameters.msa_tolerance;
            r.final_set = radius_updates >= 3 && r.same_set;
          }
        last_lambda = x;
        return r;
      });
    else
      smalbe.set_inner_solver([&](const QP::Operator   &op,
                                  const Vector<double> &b,
                                  Vector<double>       &x,
                                  const double          tolerance,
                                  const Vector<double> &gradient) {
        unsigned int calls   = 0;
        QP::Operator counted = [&](const Vector<double> &v, Vector<double> &y) {
          op(v, y);
          ++calls;
        };
        QP::MPGP::AdditionalData o = options.inner;
        o.tolerance                = tolerance;
        // MPGP starts from SMALBE's gradient and returns its own (no multiplication for
        // either).
        Vector<double>          g(gradient);
        const auto              mpgp_report = QP::MPGP(o).solve(counted, b, set, x, &g);
        QP::SMALBE::InnerReport r(mpgp_report);
        result.count_steps(mpgp_report);
        r.gradient.swap(g);
        result.n_bound += calls;
        last_lambda = x;
        return r;
      });
    // Algorithm 2 reports the change of the radius update inside its loop, MSA that of its last
    // step (0 in the first).
    smalbe.set_monitor([&](const QP::SMALBE::Step &step) {
      history_row(combined ? 0 : msa_iteration,
                  result.smalbe_iterations + step.outer_iteration + 1,
                  step.relative_feasibility,
                  step.relative_gradient,
                  combined || msa_iteration > 0 ? last_change : 0.0,
                  last_lambda,
                  step.inner_iterations);
    });
    const QP::SMALBE::Statistics report = smalbe.solve(problem, lambda, mu);
    result.smalbe_iterations += report.iterations;
    if (report.infeasible)
      {
        // The certificate in the original variables: with the projector SMALBE saw
        // λ̃ ∈ Ω − λ₀ and G̃λ̃ = 0, so αᵀẽ = αᵀG̃λ₀ and σ_Ω = σ_{Ω−λ₀} + αᵀG̃λ₀.
        double work = report.certificate_work, support = report.certificate_support;
        if (projector)
          {
            Vector<double> e_tilde(dual.coarse.n_modes());
            dual.coarse.apply_G_orthonormal(lambda0, e_tilde);
            work = report.certificate * e_tilde;
            support += work;
          }
        result.no_equilibrium = true;
        std::ostringstream text;
        text << "no equilibrium: the contact forces allowed by the current bounds (λ_N ≥ 0, "
                "‖λ_T‖ ≤ slip bound) cannot balance the loads on the floating subdomains. On a "
                "rigid motion α of those subdomains the loads do the work "
             << work << ", the contact forces at most " << support
             << " (a proof: no multiplier within the bounds satisfies Gλ = e). For a body held "
                "only by contact: the tangential loads exceed the friction coefficient times "
                "the normal force (full sliding), or the loads pull the body off the obstacle";
        result.message = text.str();
      }
    return report;
  }

  ContactSolver::Result
  ContactSolver::solve()
  {
    Result result = solve_homogenized();
    if (homogenization)
      homogenization->recover(result.lambda);
    // The equilibrium of the floating subdomains, Gλ = e, holds after SMALBE to its feasibility
    // tolerance only; restore it to rounding with a correction from the gluing rows (the same
    // choice of rows as for λ₀), which leaves the contact multipliers as solved.
    if (dual.coarse.n_modes() > 0)
      {
        Vector<double> misfit(dual.e), G_lambda;
        dual.coarse.apply_G(result.lambda, G_lambda);
        misfit -= G_lambda;
        result.lambda += dual.coarse.particular_solution(misfit, row_tier);
      }
    if (projector_enforcement)
      {
        // The multiplier of the original problem from that of the projected one.
        Vector<double> r(layout.size());
        dual.apply_F(result.lambda, r);
        r -= dual.h;
        projector_enforcement->recover_multiplier(r, result.mu);
      }
    return result;
  }

  ContactSolver::Result
  ContactSolver::solve_homogenized()
  {
    qp_tolerance = parameters.qp_tolerance;
    Result result;
    result.lambda.reinit(layout.size());
    result.mu.reinit(dual.coarse.n_modes());
    using Law          = Parameters::ContactSolver::FrictionLaw;
    using A            = Parameters::ContactSolver::Algorithm;
    const bool coulomb = parameters.friction_law == Law::coulomb && layout.n_tangential > 0;

    if (!coulomb)
      {
        // Frictionless or Tresca: one QP.
        if (layout.n_tangential > 0)
          {
            std::vector<double> g(nodes.size(), 0.0);
            for (unsigned int k = 0; k < nodes.size(); ++k)
              if (nodes[k].friction > 0) // in the units of the node's multipliers
                g[k] = parameters.slip_bound / layout.scale_of_node(k);
            set_slip_bounds(g);
          }
        const auto report       = solve_tresca(result.lambda, result.mu, result);
        result.outer_iterations = 1;
        result.converged        = report.converged;
        if (!report.infeasible)
          result.message =
            report.converged ?
              "converged" :
              std::string("SMALBE did not converge") +
                (report.inner_stalled ? " (its inner solves stalled at their iteration limit)" :
                                        "");
        return result;
      }

    // Continuation in F: stages F/n, …, F, each warm-started from the previous solution; the
    // intermediate stages need the fixed point only roughly (100 × the MSA tolerance).
    const unsigned int stages = parameters.continuation_steps;
    for (unsigned int stage = 1; stage <= stages; ++stage)
      {
        friction_scale = double(stage) / stages;
        const double msa_tolerance =
          stage < stages ? 100 * parameters.msa_tolerance : parameters.msa_tolerance;
        if (stages > 1)
          out << "Friction continuation: stage " << stage << " of " << stages << ", F × "
              << friction_scale << std::endl;
        if (parameters.algorithm == A::algorithm_2)
          solve_combined(result, msa_tolerance);
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
  ContactSolver::solve_combined(Result &result, const double msa_tolerance)
  {
    // The combined loop: SMALBE whose inner step updates the radii; repeated (warm) until the
    // slip bound agrees with F λ_N.
    result.converged = false;
    for (unsigned int call = 0; call < parameters.max_msa_iterations; ++call)
      {
        const auto report = solve_tresca(result.lambda, result.mu, result);
        if (report.infeasible)
          {
            result.outer_iterations = result.smalbe_iterations;
            return;
          }
        const auto target = coulomb_bound(result.lambda);
        last_change       = relative_change(slip_bound, target);
        if (report.converged && last_change <= msa_tolerance)
          {
            result.converged = true;
            break;
          }
        set_slip_bounds(target);
      }
    result.outer_iterations = result.smalbe_iterations;
    result.message          = result.converged ?
                                "converged" :
                                "Algorithm 2 did not converge; last relative change of the slip "
                                "bound " +
                         InputParsing::number_text(last_change);
  }

  void
  ContactSolver::solve_msa(Result &result, const double msa_tolerance, const bool cold_start)
  {
    // MSA: a cold start begins with unbounded tangential multipliers (the contact sticks:
    // g = ∞, a problem that has a solution whenever the normal contact holds the bodies; g = 0,
    // the frictionless problem, has none for a body held by friction), a warm one (a later stage
    // of the continuation in F) with g = F λ_N of the current λ; then
    // g ← (1 − ω) g + ω F λ_N (the first update takes ω = 1).
    result.converged = false;
    std::vector<double> g =
      cold_start ? std::vector<double>(nodes.size(), std::numeric_limits<double>::infinity()) :
                   coulomb_bound(result.lambda);
    set_slip_bounds(g);
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
      Vector<double>      lambda, mu;
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
        const auto report          = solve_tresca(result.lambda, result.mu, result);
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
            set_slip_bounds(previous->g);
            qp_tolerance       = parameters.qp_tolerance;
            const auto again   = solve_tresca(result.lambda, result.mu, result);
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
            last_change      = relative_change(previous->g, g);
            previous_change  = last_change;
            previous->final  = true;
            previous->lambda = result.lambda;
            previous->mu     = result.mu;
            set_slip_bounds(g);
            --msa_iteration;
            continue;
          }
        if (report.infeasible)
          {
            result.outer_iterations = msa_iteration;
            result.message +=
              " (MSA iteration " + std::to_string(msa_iteration) +
              (msa_iteration == first + 1 ? ")" :
                                            ", slip bounds g = F λ_N of the previous iteration)");
            return;
          }
        const double omega       = msa_iteration == first + 1 ? 1.0 : parameters.relaxation;
        previous                 = Step{result.lambda, result.mu, g, omega, final_precision};
        std::vector<double> next = relax(g, omega);
        last_change              = relative_change(g, next);
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
        set_slip_bounds(g);
      }
    result.message = "MSA did not converge in " + std::to_string(parameters.max_msa_iterations) +
                     " iterations; last relative change of the slip bound " +
                     InputParsing::number_text(last_change);
  }
} // namespace FetiContact
