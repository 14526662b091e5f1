#include <deal.II/base/exceptions.h>

#include <feticontact/qp/smalbe.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace FetiContact::QP
{
  using namespace dealii;

  namespace
  {
    /** a/reference, with 0/0 = 0 and a/0 = ∞ for a > 0. */
    double
    relative(const double a, const double reference)
    {
      if (reference > 0)
        return a / reference;
      return a > 0 ? std::numeric_limits<double>::infinity() : 0.;
    }

    /**
     * Inner solves at their iteration limit in a row without progress (SmalbeReport::
     * inner_stalled): neither ‖g^P‖ 1 % below its least value at such a solve nor ‖Gλ − e‖ 1 %
     * below its value at the previous one.
     */
    class InnerStallGuard
    {
    public:
      /** After an outer iteration; true once three capped ones in a row made no progress. */
      bool
      stalled(const bool capped, const double norm_gP, const double feasibility)
      {
        if (!capped)
          without_progress = 0;
        else if (norm_gP < 0.99 * best_gP || feasibility < 0.99 * last_feasibility)
          {
            best_gP          = std::min(best_gP, norm_gP);
            last_feasibility = feasibility;
            without_progress = 0;
          }
        else
          ++without_progress;
        return without_progress >= 3;
      }

    private:
      unsigned int without_progress = 0;
      double       best_gP          = std::numeric_limits<double>::infinity();
      double       last_feasibility = std::numeric_limits<double>::infinity();
    };
  } // namespace

  SmalbeReport
  smalbe(const Operator       &F,
         const Vector<double> &h,
         const SeparableSet   &set,
         const Operator       &apply_G,
         const Operator       &apply_Gt,
         const Vector<double> &e,
         Vector<double>       &lambda,
         Vector<double>       &mu,
         const SmalbeOptions  &options)
  {
    const unsigned int m = h.size(), k = e.size();
    AssertThrow(set.size() == m && lambda.size() == m,
                ExcMessage("SMALBE: sizes of h (" + std::to_string(m) + "), λ (" +
                           std::to_string(lambda.size()) + ") and the set (" +
                           std::to_string(set.size()) + ") differ."));
    if (mu.size() != k)
      {
        AssertThrow(mu.size() == 0,
                    ExcMessage("SMALBE: μ has size " + std::to_string(mu.size()) + ", e has size " +
                               std::to_string(k) + "."));
        mu.reinit(k);
      }
    AssertThrow(options.beta_M > 1, ExcMessage("SMALBE: β_M must be > 1."));
    AssertThrow(options.multiplier_step > 0 && options.multiplier_step < 2,
                ExcMessage("SMALBE: the multiplier step factor must lie in (0, 2)."));
    AssertThrow(options.tolerance > 0 && options.feasibility_tolerance > 0,
                ExcMessage("SMALBE: tolerances must be positive."));

    AssertThrow(!options.projector || e.l2_norm() == 0,
                ExcMessage("SMALBE: the projector variant needs the homogenized constraint "
                           "Gλ = 0 (e = 0); shift λ by a particular solution first."));

    SmalbeReport report;
    const double eps_mach = std::numeric_limits<double>::epsilon();

    // Norms: ‖F‖ and ‖G‖ = √‖GᵀG‖ (power-method estimates times 1.05 unless given).
    Vector<double> Gx(k), GtGx(m);
    const auto     GtG = [&](const Vector<double> &x, Vector<double> &y) {
      apply_G(x, Gx);
      apply_Gt(Gx, y);
    };
    double F_norm = options.F_norm, G_norm = options.G_norm;
    if (!(F_norm > 0))
      {
        F_norm = 1.05 * estimate_norm(F, m, options.norm_iterations);
        report.norm_estimate_multiplications += std::max(options.norm_iterations, 1u);
      }
    AssertThrow(F_norm > 0 && std::isfinite(F_norm),
                ExcMessage("SMALBE: ‖F‖ is zero or not finite."));
    if (!(G_norm > 0) && k > 0)
      G_norm = std::sqrt(1.05 * estimate_norm(GtG, m, options.norm_iterations));
    const bool   constrained = k > 0 && G_norm > 0;
    const double rho =
      options.rho > 0 ? options.rho : (constrained ? F_norm / (G_norm * G_norm) : F_norm);
    double M =
      options.M0 > 0 ? options.M0 : options.M0_factor * (constrained ? rho * G_norm : F_norm);
    const double h_norm = h.l2_norm(), e_norm = e.l2_norm();
    const double eta    = options.eta > 0 ? options.eta : options.eta_factor * h_norm;
    const double A_norm = F_norm + rho * G_norm * G_norm; // a bound of ‖F + ρGᵀG‖
    report.rho          = rho;
    report.F_norm       = F_norm;
    report.G_norm       = G_norm;

    // The Hessian of the augmented Lagrangian, counted: F + ρGᵀG, or PFP + ρQ.
    const bool     projector = options.projector && constrained;
    Vector<double> Px(projector ? m : 0), QFPx(projector ? m : 0);
    const Operator A = [&](const Vector<double> &x, Vector<double> &y) {
      if (projector)
        {
          GtG(x, GtGx);
          Px = x;
          Px -= GtGx;
          F(Px, y);
          GtG(y, QFPx);
          y -= QFPx;
          y.add(rho, GtGx);
        }
      else
        {
          F(x, y);
          if (k > 0)
            {
              GtG(x, GtGx);
              y.add(rho, GtGx);
            }
        }
      ++report.hessian_multiplications;
    };
    // The linear term of the objective: h, or Ph.
    Vector<double> h_objective(h);
    if (projector)
      {
        Vector<double> Qh(m);
        GtG(h, Qh);
        h_objective -= Qh;
      }

    // References (see the documentation): relative to the data, floored at the rounding level.
    const auto gradient_reference = [&](const Vector<double> &x) {
      const double x_norm = x.l2_norm();
      const double noise  = 64 * eps_mach * A_norm * x_norm / options.tolerance;
      return std::max(h_norm > 0 ? h_norm : F_norm * x_norm, noise);
    };
    const auto feasibility_reference = [&](const Vector<double> &x) {
      const double Gx_scale = G_norm * x.l2_norm();
      return e_norm > 0 ?
               std::max(e_norm, 64 * eps_mach * Gx_scale / options.feasibility_tolerance) :
               Gx_scale;
    };

    // The inner stopping rule at x: ‖g^P‖ ≤ max(min(M‖Gx − e‖, η), c ε_g ref_g), c = inner_floor.
    Vector<double> Gx_e(k);
    // The floor of the inner precision, lowered when SMALBE stalls (see below).
    double     floor        = options.inner_floor;
    const auto inner_target = [&](const Vector<double> &x) {
      double feasibility_x = 0;
      if (k > 0)
        {
          apply_G(x, Gx_e);
          Gx_e -= e;
          feasibility_x = Gx_e.l2_norm();
        }
      return std::max(std::min(M * feasibility_x, eta),
                      floor * options.tolerance * gradient_reference(x));
    };

    // The default inner solver: MPGP with the stopping rule evaluated at every step (one
    // application of G per step), so one call suffices.
    InnerSolver inner = options.inner_solver;
    if (!inner)
      inner = [&](const Operator       &A_inner,
                  const Vector<double> &b_inner,
                  Vector<double>       &x,
                  const double /*tolerance: replaced by the rule itself*/,
                  const Vector<double> &gradient) -> InnerReport {
        MpgpOptions inner_options = options.inner;
        inner_options.tolerance   = 0;
        inner_options.stop_when   = [&](const Vector<double> &y, const double norm_gP) {
          return norm_gP <= inner_target(y);
        };
        if (!(inner_options.step > 0))
          inner_options.step = 1.9 / A_norm;
        Vector<double> g(gradient);
        InnerReport    report(mpgp(A_inner, b_inner, set, x, inner_options, &g));
        report.gradient.swap(g);
        return report;
      };

    Vector<double> r(k), b_inner(m), Gtv(m), g(m), gP(m);
    // r = Gλ − e; returns ‖r‖.
    const auto residual = [&]() {
      if (k == 0)
        return 0.;
      apply_G(lambda, r);
      r -= e;
      return r.l2_norm();
    };
    // g_known = Aλ − b_inner at the current λ when known (from the inner solver), else empty.
    Vector<double> g_known;
    // b_inner = h − Gᵀμ + ρGᵀe = h − Gᵀ(μ − ρe) (Ph − Gᵀμ in the projector variant); a known
    // gradient follows the change of b_inner.
    const auto linear_term = [&]() {
      if (g_known.size() == m)
        g_known += b_inner;
      b_inner = h_objective;
      if (k > 0)
        {
          Vector<double> v(mu);
          v.add(-rho, e);
          apply_Gt(v, Gtv);
          b_inner -= Gtv;
        }
      if (g_known.size() == m)
        g_known -= b_inner;
    };

    double feasibility = residual();
    double L_previous  = 0;
    // Stall detection: outer iterations since ‖Gλ − e‖ last reached a new minimum.
    double       best_feasibility = std::numeric_limits<double>::infinity();
    unsigned int since_best       = 0;
    double       norm_gP          = 0;
    // Whether a relaxed start at η has made no step (then the rule is used from there on).
    bool            eta_exhausted = false;
    InnerStallGuard stall_guard;
    linear_term();
    for (unsigned int outer = 0; outer < options.max_outer_iterations; ++outer)
      {
        SmalbeStep step;
        step.outer_iteration = outer;
        step.M               = M;

        // 1. Inner solve until ‖g^P‖ ≤ max(min(M‖Gλ − e‖, η), ε_g ref_g) at its result. The
        //    tolerance passed is the rule at the start, η if λ is feasible there (else a feasible
        //    start would be solved to the final precision at once).
        //    A call that makes no step at η (λ feasible, the gradient already below η) is
        //    repeated with the rule itself, min(M · 0, η) = 0 up to the floor, as in Dostál's
        //    algorithm: otherwise λ, Gλ − e and μ would never change again (seen with one
        //    subdomain held only by contact and e = 0, where λ₀ is feasible).
        //    Once a relaxed start has made no step, later outer iterations use the rule too:
        //    with one inner call per outer iteration (the combined loop) and λ feasible in
        //    every one (k = 0: one subdomain held by Dirichlet conditions) the start would
        //    otherwise be relaxed, and stuck, forever.
        bool relaxed_start = feasibility == 0 && !eta_exhausted;
        bool capped        = false; // the last inner solve ended at its iteration limit
        while (true)
          {
            const double tolerance =
              relaxed_start ? std::max(eta, options.tolerance * gradient_reference(lambda)) :
                              inner_target(lambda);
            InnerReport inner_report = inner(A, b_inner, lambda, tolerance, g_known);
            step.inner_iterations += inner_report.iterations;
            ++step.inner_calls;
            feasibility = residual();
            if (inner_report.gradient.size() == m)
              g.swap(inner_report.gradient);
            else
              {
                A(lambda, g);
                g -= b_inner;
              }
            g_known = g;
            set.projected_gradient(lambda, g, gP);
            norm_gP = gP.l2_norm();
            const bool stuck_at_eta =
              relaxed_start && inner_report.iterations == 0 && inner_report.converged;
            relaxed_start = false;
            eta_exhausted |= stuck_at_eta;
            if (stuck_at_eta && norm_gP > inner_target(lambda) &&
                step.inner_calls < options.max_inner_calls)
              continue;
            capped = !options.inner_solver && !inner_report.converged &&
                     inner_report.iterations >= options.inner.max_iterations;
            if (norm_gP <= inner_target(lambda) || !inner_report.converged ||
                inner_report.iterations == 0 || step.inner_calls >= options.max_inner_calls)
              break;
          }
        report.inner_iterations += step.inner_iterations;
        if (stall_guard.stalled(capped, norm_gP, feasibility))
          {
            report.inner_stalled = true;
            report.iterations    = outer + 1;
            break;
          }
        // Stall: ‖Gλ − e‖ has not reached a new minimum for stall_iterations outer iterations.
        // The inner solves then stop at the floor c ε_g ref_g before they move λ enough for the
        // multiplier updates to reduce ‖Gλ − e‖ (seen with no contact at all, and on the Hertz
        // scene): lower the floor by 10, down to 1e-4 c.
        if (feasibility < best_feasibility)
          {
            best_feasibility = feasibility;
            since_best       = 0;
          }
        else if (++since_best >= options.stall_iterations && floor > 1e-4 * options.inner_floor)
          {
            floor /= 10;
            since_best = 0;
            ++report.floor_reductions;
          }
        report.inner_calls += step.inner_calls;

        // L(λ, μ_k, ρ) = ½λᵀ(g − b_inner) − μᵀe + ρ/2‖e‖² with g = Aλ − b_inner.
        double L = 0;
        for (unsigned int i = 0; i < m; ++i)
          L += lambda[i] * (g[i] - b_inner[i]);
        L = L / 2 - (k > 0 ? mu * e : 0.) + rho / 2 * e_norm * e_norm;

        report.iterations           = outer + 1;
        report.relative_gradient    = relative(norm_gP, gradient_reference(lambda));
        report.relative_feasibility = relative(feasibility, feasibility_reference(lambda));
        const bool converged        = report.relative_gradient <= options.tolerance &&
                               report.relative_feasibility <= options.feasibility_tolerance;

        // 3. μ_{k+1} = μ_k + sρ(Gλ_k − e) (s = 1 unless over-relaxed).
        if (k > 0)
          mu.add(options.multiplier_step * rho, r);

        // 4. M_{k+1}.
        if (!converged && outer > 0 && L < L_previous + rho / 2 * feasibility * feasibility &&
            (!options.same_problem || options.same_problem()))
          {
            M /= options.beta_M;
            step.M_decreased = true;
          }
        L_previous = L;

        step.hessian_multiplications = report.hessian_multiplications;
        step.relative_gradient       = report.relative_gradient;
        step.relative_feasibility    = report.relative_feasibility;
        step.lagrangian              = L;
        if (options.monitor)
          options.monitor(step);
        // Infeasibility: α = −r/‖r‖ with αᵀe > σ_Ω(Gᵀα) proves that Gλ = e has no solution
        // in Ω (the multiplier updates would then grow μ without bound).
        // Only for a final set (SmalbeOptions::set_final).
        if (!converged && k > 0 && feasibility > 0 && (!options.set_final || options.set_final()))
          {
            Vector<double> alpha(r);
            alpha *= -1.0 / feasibility;
            apply_Gt(alpha, Gtv);
            const double work = alpha * e, support = set.support(Gtv, 1e-12);
            if (work - support > 1e-6 * (std::abs(work) + std::abs(support)))
              {
                report.infeasible          = true;
                report.certificate_work    = work;
                report.certificate_support = support;
                report.certificate         = alpha;
                break;
              }
          }

        if (converged)
          {
            report.converged = true;
            break;
          }
        linear_term();
      }

    report.relative_residual = report.relative_gradient;
    report.M                 = M;
    report.mu                = mu;
    return report;
  }
} // namespace FetiContact::QP
