#include <deal.II/base/exceptions.h>

#include <feticontact/qp/mpgp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace FetiContact::QP
{
  using namespace dealii;

  double
  estimate_norm(const Operator &A, const unsigned int n, const unsigned int iterations)
  {
    if (n == 0)
      return 0;
    // Deterministic pseudo-random start (minstd_rand's sequence is fixed by the standard).
    std::minstd_rand random(20120101);
    Vector<double>   v(n), Av(n);
    for (auto &vi : v)
      vi = double(random()) / double(std::minstd_rand::max()) - 0.5;
    v /= v.l2_norm();
    double estimate = 0;
    for (unsigned int k = 0; k < std::max(iterations, 1u); ++k)
      {
        A(v, Av);
        estimate = Av.l2_norm();
        if (!(estimate > 0) || !std::isfinite(estimate))
          return estimate > 0 ? estimate : 0.;
        v.equ(1. / estimate, Av);
      }
    return estimate;
  }

  double
  estimate_mean_diagonal(const Operator &A, const unsigned int n, const unsigned int probes)
  {
    if (n == 0)
      return 0;
    std::minstd_rand random(20260101);
    Vector<double>   v(n), Av(n);
    double           sum = 0;
    for (unsigned int k = 0; k < std::max(probes, 1u); ++k)
      {
        for (auto &vi : v)
          vi = random() % 2 == 0 ? 1. : -1.;
        A(v, Av);
        sum += v * Av;
      }
    return sum / (double(std::max(probes, 1u)) * n);
  }

  MpgpReport
  mpgp(const Operator       &A,
       const Vector<double> &b,
       const SeparableSet   &set,
       Vector<double>       &x,
       const MpgpOptions    &options,
       Vector<double>       *gradient_in_out)
  {
    const unsigned int n = b.size();
    AssertThrow(set.size() == n && x.size() == n,
                ExcMessage("MPGP: sizes of b (" + std::to_string(n) + "), x (" +
                           std::to_string(x.size()) + ") and the set (" +
                           std::to_string(set.size()) + ") differ."));
    AssertThrow(options.gamma > 0, ExcMessage("MPGP: Γ must be positive."));

    MpgpReport report;
    const auto multiply = [&](const Vector<double> &v, Vector<double> &w) {
      A(v, w);
      ++report.hessian_multiplications;
    };

    double alpha_bar = options.step;
    if (!(alpha_bar > 0))
      {
        const unsigned int iterations = std::max(options.norm_iterations, 1u);
        const double       norm       = estimate_norm(A, n, iterations);
        report.hessian_multiplications += iterations;
        report.norm_estimate_multiplications = iterations;
        if (!(norm > 0) || !std::isfinite(norm))
          {
            // A vanishes on the start vector (or n = 0): nothing sensible to iterate with.
            report.converged = (n == 0);
            if (gradient_in_out)
              gradient_in_out->reinit(0);
            return report;
          }
        alpha_bar = 1.9 / (1.05 * norm);
      }
    report.step = alpha_bar;

    using DiscMode      = SeparableSet::DiscMode;
    const DiscMode mode = options.disc_rotations ? DiscMode::rotations : DiscMode::fixed;
    Vector<double> g(n), p(n), Ap(n), Hp(n), phi(n), beta(n), y(n), x_old, g_old, phi_old;
    const double   b_norm  = b.l2_norm();
    double         norm_gP = 0;
    // z = M⁻¹φ, the search direction before conjugation: φ itself, or with rotations φ
    // divided on the tangents of pressed discs by 1 + (σ_k/r_k)/a with a = MpgpOptions::
    // arc_scale or ‖A‖ (the curvature of a small, strongly pressed circle dominates the Hessian
    // along it; SeparableSet::precondition_arcs).
    const bool   precondition = mode == DiscMode::rotations && options.precondition_rotations;
    const double arc_scale    = options.arc_scale > 0 ? options.arc_scale : 1.9 / alpha_bar;
    // With a preconditioner in face: z = D^(−½) R_F M R_F D^(−½) φ (D the arc factor, R_F the
    // restriction to the face, which φ already satisfies).
    const bool     in_face = static_cast<bool>(options.preconditioner);
    Vector<double> z(n), Mz(in_face ? n : 0);
    const auto     update_sets = [&]() {
      set.free_gradient(x, g, phi, mode);
      set.chopped_gradient(x, g, beta, mode);
      norm_gP = std::sqrt(phi.norm_sqr() + beta.norm_sqr()); // φ·β = 0
      z       = phi;
      if (precondition)
        set.precondition_arcs(x, g, arc_scale, z, in_face ? 0.5 : 1.);
      if (in_face)
        {
          options.preconditioner(z, Mz);
          ++report.preconditioner_applications;
          set.free_gradient(x, Mz, z, mode);
          if (precondition)
            set.precondition_arcs(x, g, arc_scale, z, 0.5);
        }
    };
    // A bound of ‖g − (Ax − b)‖ left by recursive gradient updates (MpgpOptions::
    // recursive_gradient_tolerance); zero whenever g was recomputed.
    double     gradient_error = 0;
    const auto gradient       = [&]() {
      multiply(x, g);
      g -= b;
      gradient_error = 0;
    };
    // f(x) − f(x_old) = ½(x − x_old)ᵀ(g + g_old) (exact for a quadratic), and whether it is an
    // increase beyond the rounding level (the projection onto a disc is exact only to ε r, times
    // the multiplier g·ν).
    const auto increased = [&]() {
      double df = 0, noise = 0;
      for (unsigned int i = 0; i < n; ++i)
        {
          df += (x[i] - x_old[i]) * (g[i] + g_old[i]);
          noise += std::abs(x[i]) * (std::abs(g[i]) + std::abs(g_old[i]));
        }
      return df > 32 * std::numeric_limits<double>::epsilon() * noise;
    };
    // The gradient at x = P_Ω(x_old − α p), with g = g_old and Ap on entry. With
    // MpgpOptions::recursive_gradient_tolerance > 0: g ← g − αAp, leaving out A d for the return
    // d = x − (x_old − α p) onto Ω, if the error bound (2/ᾱ ≥ ‖A‖) summed since the last
    // recomputation stays below η‖g^P‖ and the energy test on the updated g sees no increase
    // (returns true); otherwise g ← Ax − b (returns false).
    const auto gradient_after_projection = [&](const double alpha) {
      if (options.recursive_gradient_tolerance > 0)
        {
          y = x;
          y -= x_old;
          y.add(alpha, p);
          const double drift = 2. / alpha_bar * y.l2_norm();
          if (gradient_error + drift <= options.recursive_gradient_tolerance * norm_gP)
            {
              g.add(-alpha, Ap);
              gradient_error += drift;
              if (!increased())
                {
                  ++report.recursive_gradient_updates;
                  return true;
                }
            }
        }
      gradient();
      return false;
    };
    // The projected gradient step x ← P_Ω(x_old − ᾱ g_old), which decreases f for ᾱ ≤ 2/‖A‖.
    const auto projected_gradient_step = [&]() {
      x = x_old;
      x.add(-alpha_bar, g_old);
      set.project(x);
      gradient();
      ++report.proportioning_fallbacks;
    };

    // The caller's gradient Ax₀ − b stands for the first multiplication if x₀ ∈ Ω already: if
    // the projection moves x₀ by no more than the rounding of a projection onto a circle
    // (x₀ returned by an earlier solve), the known gradient is off by at most ‖A‖ times that.
    const bool known_gradient = gradient_in_out && gradient_in_out->size() == n;
    if (known_gradient)
      x_old = x;
    set.project(x);
    bool moved = true;
    if (known_gradient)
      {
        y = x;
        y -= x_old;
        moved = y.linfty_norm() > 4 * std::numeric_limits<double>::epsilon() * x.linfty_norm();
      }
    if (!moved)
      g = *gradient_in_out;
    else
      gradient();
    update_sets();
    p              = z;
    bool p_is_phi  = true;
    bool breakdown = false;

    const auto stop = [&]() {
      return norm_gP <= options.tolerance || (options.stop_when && options.stop_when(x, norm_gP));
    };
    // Every stopping decision is made on the exact gradient.
    const auto done = [&]() {
      if (!stop())
        return false;
      if (gradient_error == 0)
        return true;
      gradient();
      update_sets();
      return stop();
    };
    bool converged = done();
    while (!converged && std::isfinite(norm_gP) && !breakdown &&
           report.iterations < options.max_iterations)
      {
        // Proportionality: ‖β‖² ≤ Γ² φ̃ᵀφ with φ̃ = (x − P_Ω(x − ᾱφ))/ᾱ.
        y = x;
        y.add(-alpha_bar, phi);
        set.project(y);
        double phi_tilde_phi = 0;
        for (unsigned int i = 0; i < n; ++i)
          phi_tilde_phi += (x[i] - y[i]) * phi[i];
        phi_tilde_phi /= alpha_bar;

        if (beta.norm_sqr() <= options.gamma * options.gamma * phi_tilde_phi)
          {
            // gᵀp = φᵀp: p lives where φ does (free blocks, tangents of active discs). φᵀp
            // avoids the cancellation of the large normal parts of g on pressed discs, which
            // makes gᵀp meaningless (even negative) once φ is near the rounding level of g.
            double gp = phi * p;
            if (!(gp > 0) && !p_is_phi)
              {
                p        = z;
                p_is_phi = true;
                gp       = phi * p;
              }
            multiply(p, Ap);
            // Along the circles of active discs the second derivative of f gains the curvature
            // term (SeparableSet::arc_curvature); without rotations it is zero.
            const bool   arc       = mode == DiscMode::rotations && set.moves_active_discs(x, p);
            const double curvature = p * Ap + (arc ? set.arc_curvature(x, g, p) : 0.);
            if (!(curvature > 0) || !(gp > 0))
              {
                if (p_is_phi)
                  breakdown = true; // A not positive definite on φ, or φ = 0 at rounding level
                else
                  {
                    p        = z;
                    p_is_phi = true;
                  }
                continue;
              }
            const double alpha_cg = gp / curvature;
            const double alpha_f  = set.max_feasible_step(x, p, mode);
            if (alpha_cg <= alpha_f)
              {
                // Conjugate gradient step; with rotations along the arcs of the active discs.
                if (arc)
                  {
                    x_old   = x;
                    g_old   = g;
                    phi_old = phi;
                  }
                x.add(-alpha_cg, p);
                set.project(x);
                // With rotations the projection back onto the circles moved x off the line:
                // recompute g, and fall back to the projected gradient step if f increased.
                bool fallback = false;
                if (!arc)
                  g.add(-alpha_cg, Ap);
                else if (!gradient_after_projection(alpha_cg))
                  {
                    fallback = increased();
                    if (fallback)
                      projected_gradient_step();
                  }
                update_sets();
                if (fallback)
                  {
                    p        = z;
                    p_is_phi = true;
                  }
                else
                  {
                    double gamma_cg = (z * Ap) / curvature;
                    if (arc)
                      {
                        // Hestenes–Stiefel with the change of the tangential gradient along the
                        // step, both transported to the tangent spaces at the new x: it carries the
                        // curvature of the circles as it is along the step, not only at its start.
                        Hp = phi_old;
                        Hp -= phi;
                        set.remove_normal_parts(x, Hp);
                        set.remove_normal_parts(x, p);
                        const double pHp = p * Hp;
                        gamma_cg         = pHp > 0 ? (z * Hp) / pHp : 0.;
                      }
                    p.sadd(-gamma_cg, 1., z); // p ← z − γ p
                    set.remove_normal_parts(x, p);
                    p_is_phi = false;
                    ++report.cg_steps;
                  }
              }
            else
              {
                bool expanded = false;
                if (options.expansion == MpgpOptions::Expansion::projected_cg)
                  {
                    // The whole conjugate gradient step, projected: every constraint that it
                    // crosses becomes active at once. Kept only if f decreased.
                    x_old                     = x;
                    g_old                     = g;
                    const double error_before = gradient_error;
                    x.add(-alpha_cg, p);
                    set.project(x);
                    expanded = gradient_after_projection(alpha_cg) || !increased();
                    if (!expanded)
                      {
                        x              = x_old;
                        g              = g_old;
                        gradient_error = error_before;
                        ++report.expansion_fallbacks;
                      }
                  }
                if (!expanded)
                  {
                    // Expansion step: feasible half step, then the fixed-step projected step
                    // along the free gradient of the fixed-disc mode (its decrease of f is
                    // guaranteed for ᾱ ≤ 2/‖A‖; a rotation of a strongly pressed disc by ᾱ
                    // would not be).
                    x.add(-alpha_f, p);
                    set.project(x);
                    g.add(-alpha_f, Ap);
                    set.free_gradient(x, g, phi, DiscMode::fixed);
                    x.add(-alpha_bar, phi);
                    set.project(x);
                    gradient();
                  }
                update_sets();
                p        = z;
                p_is_phi = true;
                ++report.expansion_steps;
              }
          }
        else
          {
            // Proportioning step along the chopped gradient.
            if (mode == DiscMode::rotations || !set.nonzero_on_discs(beta))
              {
                // β points into Ω along a line (on discs, with rotations, along the inward
                // normal): exact line search, cut at the far end of the feasible segment.
                multiply(beta, Ap);
                const double dAd = beta * Ap;
                if (!(dAd > 0))
                  {
                    breakdown = true;
                    continue;
                  }
                const double alpha = std::min((beta * beta) / dAd, set.max_feasible_step(x, beta));
                x.add(-alpha, beta);
                set.project(x);
                g.add(-alpha, Ap);
              }
            else
              {
                x_old        = x;
                g_old        = g;
                double alpha = alpha_bar;
                if (options.proportioning_line_search)
                  {
                    // Minimizer of the second-order model of f along the arc P_Ω(x − αβ).
                    multiply(beta, Ap);
                    const double curvature = beta * Ap + set.arc_curvature(x, g, beta);
                    if (!(curvature > 0))
                      {
                        breakdown = true;
                        continue;
                      }
                    alpha = (beta * beta) / curvature;
                  }
                x.add(-alpha, beta);
                set.project(x);
                gradient();
                if (increased())
                  projected_gradient_step();
              }
            update_sets();
            p        = z;
            p_is_phi = true;
            ++report.proportioning_steps;
          }
        ++report.iterations;
        if (options.monitor)
          options.monitor(report.iterations, norm_gP);
        converged = done();
      }

    if (gradient_error > 0)
      {
        // Stopped without convergence (steps exhausted, breakdown): report the exact ‖g^P‖.
        gradient();
        update_sets();
      }
    if (gradient_in_out)
      *gradient_in_out = g;
    report.projected_gradient_norm = norm_gP;
    report.relative_residual       = b_norm > 0 ? norm_gP / b_norm : norm_gP;
    report.converged               = converged;
    return report;
  }
} // namespace FetiContact::QP
