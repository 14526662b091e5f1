#include <deal.II/base/exceptions.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/base/reproducible_partitioner.h>
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
     * Inner solves at their iteration limit in a row without progress (Statistics::
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

  void
  SMALBEParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Maximum iterations",
                      "auto",
                      Patterns::Anything(),
                      "A positive integer, the limit of SMALBE's outer iterations per QP solve, "
                      "or 'auto': 200 for algorithm 2 with Coulomb friction (per call of its "
                      "loop, which is then repeated warm), 2000 otherwise.");
    prm.declare_entry(
      "Penalty factor",
      "auto",
      Patterns::Anything(),
      "The penalty ρ as a multiple in (0, 1e4] of the estimated norm of the FETI part of the "
      "Hessian (‖PFP‖ for mpgp with the projector, ‖F‖ otherwise), or 'auto': 5 for mpgp, 1 for "
      "polygonal, 0.1 for algorithm 1, 0.03 for algorithm 2. The block Gauss–Seidel of "
      "algorithms 1 and 2 converges slowly when ρG̃ᵀG̃ couples λ_c and λ_T strongly.");
    prm.declare_entry("Multiplier step factor",
                      "1",
                      Patterns::Double(0, 2),
                      "s ∈ (0, 2) in the multiplier update ν ← ν + sρ(Gλ − e); 1 is SMALBE as "
                      "published, s > 1 over-relaxes the update.");
    prm.declare_entry("Inner tolerance floor",
                      "1",
                      Patterns::Double(0, 1),
                      "c ∈ (0, 1]: the inner solves stop no later than at c × the final gradient "
                      "tolerance. Below 1 the inner solves are more precise than SMALBE needs, "
                      "which can help a body held only by frictionless contact, where ‖Gλ − e‖ "
                      "may otherwise stall a few times above its tolerance.");
    prm.declare_entry("Equality constraint",
                      "projector",
                      Patterns::Selection("projector|penalty"),
                      "How Gλ = e (the equilibrium of floating subdomains) is enforced: "
                      "'projector': λ = λ₀ + λ̃ with the least-norm Gλ₀ = e, the Hessian PFP + ρQ "
                      "of Farhat–Mandel–Roux (the natural coarse space); 'penalty': the Hessian "
                      "F + ρG̃ᵀG̃ with G̃ the orthonormalized G.");
    prm.declare_entry("Hessian norm bound",
                      "auto",
                      Patterns::Selection("auto|sum|max"),
                      "The bound of ‖A‖ behind MPGP's fixed step ᾱ = 1.9/‖A‖: 'sum' ‖F‖ + ρ, "
                      "valid for either equality constraint; 'max' max(‖F‖, ρ), valid only for "
                      "the projector, whose Hessian PFP + ρQ acts on the complementary orthogonal "
                      "subspaces ker G̃ and range G̃ᵀ. 'auto': max for mpgp, sum otherwise.");
  }

  void
  SMALBEParameters::parse_parameters(ParameterHandler &prm)
  {
    const std::string limit_text = InputParsing::trim(prm.get("Maximum iterations"));
    if (limit_text != "auto")
      {
        const std::string what  = "Contact solver/SMALBE/Maximum iterations";
        const double      limit = InputParsing::parse_double(limit_text, what);
        require(limit >= 1 && limit == std::floor(limit) && limit <= 1e9,
                what + " must be 'auto' or a positive integer; got '" + limit_text + "'.");
        max_outer_iterations = static_cast<unsigned int>(limit);
      }
    const std::string penalty_text = InputParsing::trim(prm.get("Penalty factor"));
    if (penalty_text != "auto")
      {
        const std::string what = "Contact solver/SMALBE/Penalty factor";
        penalty_factor         = InputParsing::parse_double(penalty_text, what);
        require(penalty_factor > 0,
                what + " must be 'auto' or a number above 0; got '" + penalty_text + "'.");
        // The rounding level of the Hessian F + ρG̃ᵀG̃ grows with ρ, and with it the floor of
        // the relative stopping tests: on the brick (k = 8) a factor of 1e6 left an error of
        // 3.5e-7 at the reference accuracy (1e-10) while SMALBE reported convergence; 1e4 kept
        // 2e-9 (and took 15 times the multiplications of the default).
        require(penalty_factor <= 1e4,
                what +
                  " must not exceed 1e4 (the rounding of the Hessian, which grows with the "
                  "penalty, would then decide when SMALBE stops); got '" +
                  penalty_text + "'.");
      }
    multiplier_step = prm.get_double("Multiplier step factor");
    require(
      multiplier_step > 0 && multiplier_step < 2,
      "Contact solver/SMALBE/Multiplier step factor must lie in (0, 2) (the method of multipliers "
      "diverges from 2 on); got " +
        prm.get("Multiplier step factor") + ".");
    inner_floor = prm.get_double("Inner tolerance floor");
    require(inner_floor > 0,
            "Contact solver/SMALBE/Inner tolerance floor must lie in (0, 1]; got 0.");
    equality_constraint     = prm.get("Equality constraint") == "projector" ?
                                EqualityConstraint::projector :
                                EqualityConstraint::penalty;
    const std::string bound = prm.get("Hessian norm bound");
    require(
      bound != "max" || equality_constraint == EqualityConstraint::projector,
      "Contact solver/SMALBE/Hessian norm bound = max holds only with Equality constraint = projector "
      "(the Hessian F + ρG̃ᵀG̃ of the penalty variant is bounded by the sum).");
    if (bound != "auto")
      hessian_norm_bound = bound == "max" ? HessianNormBound::max : HessianNormBound::sum;
    if (equality_constraint != EqualityConstraint::projector)
      hessian_norm_bound = HessianNormBound::sum;
  }

  template <typename VectorType>
  SMALBE<VectorType>::SMALBE()
    : additional_data()
  {}

  template <typename VectorType>
  SMALBE<VectorType>::SMALBE(const AdditionalData &data)
    : additional_data(data)
  {}

  template <typename VectorType>
  void
  SMALBE<VectorType>::set_inner_solver(InnerSolver solver)
  {
    inner_solver = std::move(solver);
  }

  template <typename VectorType>
  void
  SMALBE<VectorType>::set_monitor(std::function<void(const Step &)> new_monitor)
  {
    monitor = std::move(new_monitor);
  }

  template <typename VectorType>
  typename SMALBE<VectorType>::AdditionalData &
  SMALBE<VectorType>::data()
  {
    return additional_data;
  }

  template <typename VectorType>
  void
  SMALBE<VectorType>::choose_scales()
  {
    // Norms: ‖F‖ and ‖G‖ = √‖GᵀG‖ (power-method estimates times 1.05 unless given).
    const AdditionalData &o = additional_data;
    F_norm                  = o.F_norm;
    G_norm                  = o.G_norm;
    if (!(F_norm > 0))
      {
        F_norm = 1.05 * estimate_norm(problem->hessian, problem->linear_term, o.norm_iterations);
        statistics.norm_estimate_multiplications += std::max(o.norm_iterations, 1u);
      }
    AssertThrow(F_norm > 0 && std::isfinite(F_norm),
                ExcMessage("SMALBE: ‖F‖ is zero or not finite."));
    if (!(G_norm > 0) && k > 0)
      {
        const Operator<VectorType> GtG = [&](const VectorType &x, VectorType &y) {
          problem->G(x, Gx);
          problem->Gt(Gx, y);
        };
        G_norm = std::sqrt(1.05 * estimate_norm(GtG, problem->linear_term, o.norm_iterations));
      }
    const bool constrained = k > 0 && G_norm > 0;
    rho               = o.rho > 0 ? o.rho : (constrained ? F_norm / (G_norm * G_norm) : F_norm);
    M                 = o.M0 > 0 ? o.M0 : o.M0_factor * (constrained ? rho * G_norm : F_norm);
    h_norm            = problem->linear_term_norm();
    e_norm            = problem->e.l2_norm();
    eta               = o.eta > 0 ? o.eta : o.eta_factor * h_norm;
    A_norm            = F_norm + rho * G_norm * G_norm; // a bound of ‖F + ρGᵀG‖
    statistics.rho    = rho;
    statistics.F_norm = F_norm;
    statistics.G_norm = G_norm;
  }

  template <typename VectorType>
  void
  SMALBE<VectorType>::apply_A(const VectorType &x, VectorType &y)
  {
    if (problem->augmented_hessian && k > 0)
      problem->augmented_hessian(rho, x, y);
    else
      {
        problem->hessian(x, y);
        if (k > 0)
          {
            problem->G(x, Gx);
            problem->Gt(Gx, GtGx);
            y.add(rho, GtGx);
          }
      }
    ++statistics.hessian_multiplications;
  }

  template <typename VectorType>
  double
  SMALBE<VectorType>::residual()
  {
    if (k == 0)
      return 0.;
    problem->G(*lambda, r);
    r -= problem->e;
    return r.l2_norm();
  }

  template <typename VectorType>
  double
  SMALBE<VectorType>::gradient_reference(const VectorType &x) const
  {
    const double eps_mach = std::numeric_limits<double>::epsilon();
    const double x_norm   = l2_norm(x);
    const double noise    = 64 * eps_mach * A_norm * x_norm / additional_data.tolerance;
    return std::max(h_norm > 0 ? h_norm : F_norm * x_norm, noise);
  }

  template <typename VectorType>
  double
  SMALBE<VectorType>::feasibility_reference(const VectorType &x) const
  {
    const double eps_mach = std::numeric_limits<double>::epsilon();
    const double Gx_scale = G_norm * l2_norm(x);
    return e_norm > 0 ?
             std::max(e_norm, 64 * eps_mach * Gx_scale / additional_data.feasibility_tolerance) :
             Gx_scale;
  }

  template <typename VectorType>
  double
  SMALBE<VectorType>::inner_target(const VectorType &x)
  {
    double feasibility_x = 0;
    if (k > 0)
      {
        problem->G(x, Gx_e);
        Gx_e -= problem->e;
        feasibility_x = Gx_e.l2_norm();
      }
    return std::max(std::min(M * feasibility_x, eta),
                    floor * additional_data.tolerance * gradient_reference(x));
  }

  template <typename VectorType>
  void
  SMALBE<VectorType>::update_linear_term()
  {
    // b = h − Gᵀμ + ρGᵀe = h − Gᵀ(μ − ρe); a known gradient follows the change of b.
    if (g_known.size() == m)
      g_known += b;
    b = problem->linear_term;
    if (k > 0)
      {
        Vector<double> v(*mu);
        v.add(-rho, problem->e);
        problem->Gt(v, Gtv);
        b -= Gtv;
      }
    if (g_known.size() == m)
      g_known -= b;
  }

  template <typename VectorType>
  typename SMALBE<VectorType>::InnerReport
  SMALBE<VectorType>::default_inner_solve(const VectorType &b_inner, const double /*tolerance*/)
  {
    // MPGP with the stopping rule evaluated at every step (one application of G per step), so
    // one call suffices; the tolerance passed is replaced by the rule itself.
    typename MPGP<VectorType>::AdditionalData data(additional_data.inner);
    data.tolerance = 0;
    data.stop_when = [&](const VectorType &y, const double norm) {
      return norm <= inner_target(y);
    };
    if (!(data.step > 0))
      data.step = 1.9 / A_norm;
    MPGP<VectorType> mpgp(data);
    VectorType       gradient(g_known);
    InnerReport      report(mpgp.solve([&](const VectorType &x, VectorType &y) { apply_A(x, y); },
                                  b_inner,
                                  *problem->set,
                                  *lambda,
                                  &gradient));
    report.gradient.swap(gradient);
    report.capped = !report.converged && report.iterations >= data.max_iterations;
    return report;
  }

  template <typename VectorType>
  bool
  SMALBE<VectorType>::inner_solves(Step &step, InnerReport &last)
  {
    // Until ‖g^P‖ ≤ max(min(M‖Gλ − e‖, η), ε_g ref_g) at the result. The tolerance passed is the
    // rule at the start, η if λ is feasible there (else a feasible start would be solved to the
    // final precision at once). A call that makes no step at η (λ feasible, the gradient
    // already below η) is repeated with the rule itself, min(M · 0, η) = 0 up to the floor, as
    // in Dostál's algorithm: otherwise λ, Gλ − e and μ would never change again (seen with one
    // subdomain held only by contact and e = 0, where λ₀ is feasible). Once a relaxed start has
    // made no step, later outer iterations use the rule too: with one inner call per outer
    // iteration (the combined loop) and λ feasible in every one (k = 0: one subdomain held by
    // Dirichlet conditions) the start would otherwise be relaxed, and stuck, forever.
    const AdditionalData      &o             = additional_data;
    bool                       relaxed_start = feasibility == 0 && !eta_exhausted;
    const Operator<VectorType> A = [&](const VectorType &x, VectorType &y) { apply_A(x, y); };
    while (true)
      {
        const double tolerance = relaxed_start ?
                                   std::max(eta, o.tolerance * gradient_reference(*lambda)) :
                                   inner_target(*lambda);
        last                   = inner_solver ? inner_solver(A, b, *lambda, tolerance, g_known) :
                                                default_inner_solve(b, tolerance);
        step.inner_iterations += last.iterations;
        ++step.inner_calls;
        feasibility = residual();
        if (last.gradient.size() == m)
          g.swap(last.gradient);
        else
          {
            apply_A(*lambda, g);
            g -= b;
          }
        g_known = g;
        problem->set->projected_gradient(*lambda, g, gP);
        norm_gP                 = l2_norm(gP);
        const bool stuck_at_eta = relaxed_start && last.iterations == 0 && last.converged;
        relaxed_start           = false;
        eta_exhausted |= stuck_at_eta;
        if (stuck_at_eta && norm_gP > inner_target(*lambda) && step.inner_calls < o.max_inner_calls)
          continue;
        const bool capped = last.capped;
        if (norm_gP <= inner_target(*lambda) || !last.converged || last.iterations == 0 ||
            step.inner_calls >= o.max_inner_calls)
          return capped;
      }
  }

  template <typename VectorType>
  void
  SMALBE<VectorType>::watch_feasibility()
  {
    // Stall: ‖Gλ − e‖ has not reached a new minimum for stall_iterations outer iterations. The
    // inner solves then stop at the floor c ε_g ref_g before they move λ enough for the
    // multiplier updates to reduce ‖Gλ − e‖ (seen with no contact at all, and on the Hertz
    // scene): lower the floor by 10, down to 1e-4 c.
    if (feasibility < best_feasibility)
      {
        best_feasibility = feasibility;
        since_best       = 0;
      }
    else if (++since_best >= additional_data.stall_iterations &&
             floor > 1e-4 * additional_data.inner_floor)
      {
        floor /= 10;
        since_best = 0;
        ++statistics.floor_reductions;
      }
  }

  template <typename VectorType>
  double
  SMALBE<VectorType>::lagrangian() const
  {
    const VectorType &l = *lambda;
    const double      L = Reductions<VectorType>::sum(l, [&](const unsigned int i) {
      return l.local_element(i) * (g.local_element(i) - b.local_element(i));
    });
    return L / 2 - (k > 0 ? *mu * problem->e : 0.) + rho / 2 * e_norm * e_norm;
  }

  template <typename VectorType>
  bool
  SMALBE<VectorType>::infeasibility_proved()
  {
    // α = −r/‖r‖ with αᵀe > σ_Ω(Gᵀα) proves that Gλ = e has no solution in Ω (the multiplier
    // updates would then grow μ without bound).
    Vector<double> alpha(r);
    alpha *= -1.0 / feasibility;
    problem->Gt(alpha, Gtv);
    const double work = alpha * problem->e, support = problem->set->support(Gtv, 1e-12);
    if (!(work - support > 1e-6 * (std::abs(work) + std::abs(support))))
      return false;
    statistics.infeasible          = true;
    statistics.certificate_work    = work;
    statistics.certificate_support = support;
    statistics.certificate         = alpha;
    return true;
  }

  template <typename VectorType>
  typename SMALBE<VectorType>::Statistics
  SMALBE<VectorType>::solve(const Problem<VectorType> &problem_in,
                            VectorType                &lambda_in,
                            Vector<double>            &mu_in)
  {
    const AdditionalData &o = additional_data;
    m                       = problem_in.size();
    k                       = problem_in.e.size();
    AssertThrow(problem_in.set &&
                  problem_in.set->size() == problem_in.linear_term.locally_owned_size() &&
                  lambda_in.size() == m,
                ExcMessage("SMALBE: sizes of h (" + std::to_string(m) + "), λ (" +
                           std::to_string(lambda_in.size()) + ") and the set differ."));
    if (mu_in.size() != k)
      {
        AssertThrow(mu_in.size() == 0,
                    ExcMessage("SMALBE: μ has size " + std::to_string(mu_in.size()) +
                               ", e has size " + std::to_string(k) + "."));
        mu_in.reinit(k);
      }
    AssertThrow(o.beta_M > 1, ExcMessage("SMALBE: β_M must be > 1."));
    AssertThrow(o.multiplier_step > 0 && o.multiplier_step < 2,
                ExcMessage("SMALBE: the multiplier step factor must lie in (0, 2)."));
    AssertThrow(o.tolerance > 0 && o.feasibility_tolerance > 0,
                ExcMessage("SMALBE: tolerances must be positive."));
    problem    = &problem_in;
    lambda     = &lambda_in;
    mu         = &mu_in;
    statistics = Statistics();
    for (auto *v : {&Gx, &Gx_e, &r})
      v->reinit(k);
    for (auto *v : {&GtGx, &b, &Gtv, &g, &gP})
      v->reinit(problem_in.linear_term);
    g_known = VectorType();
    choose_scales();

    floor                      = o.inner_floor;
    feasibility                = residual();
    best_feasibility           = std::numeric_limits<double>::infinity();
    since_best                 = 0;
    norm_gP                    = 0;
    eta_exhausted              = false;
    double          L_previous = 0;
    InnerStallGuard stall_guard;
    update_linear_term();
    for (unsigned int outer = 0; outer < o.max_outer_iterations; ++outer)
      {
        Step step;
        step.outer_iteration = outer;
        step.M               = M;
        InnerReport last;
        const bool  capped = inner_solves(step, last);
        statistics.inner_iterations += step.inner_iterations;
        if (stall_guard.stalled(capped, norm_gP, feasibility))
          {
            statistics.inner_stalled = true;
            statistics.iterations    = outer + 1;
            break;
          }
        watch_feasibility();
        statistics.inner_calls += step.inner_calls;

        const double L                  = lagrangian();
        statistics.iterations           = outer + 1;
        statistics.relative_gradient    = relative(norm_gP, gradient_reference(*lambda));
        statistics.relative_feasibility = relative(feasibility, feasibility_reference(*lambda));
        const bool converged            = statistics.relative_gradient <= o.tolerance &&
                               statistics.relative_feasibility <= o.feasibility_tolerance;

        // μ_{k+1} = μ_k + sρ(Gλ_k − e) (s = 1 unless over-relaxed).
        if (k > 0)
          mu->add(o.multiplier_step * rho, r);
        // M_{k+1}: divided by β_M when L did not increase enough, over the same set.
        if (!converged && outer > 0 && L < L_previous + rho / 2 * feasibility * feasibility &&
            last.same_set)
          {
            M /= o.beta_M;
            step.M_decreased = true;
          }
        L_previous = L;

        step.hessian_multiplications = statistics.hessian_multiplications;
        step.relative_gradient       = statistics.relative_gradient;
        step.relative_feasibility    = statistics.relative_feasibility;
        step.lagrangian              = L;
        if (monitor)
          monitor(step);
        if (!converged && k > 0 && feasibility > 0 && last.final_set && infeasibility_proved())
          break;
        if (converged)
          {
            statistics.converged = true;
            break;
          }
        update_linear_term();
      }

    statistics.relative_residual = statistics.relative_gradient;
    statistics.M                 = M;
    statistics.mu                = *mu;
    return statistics;
  }
  template class SMALBE<DistributedVector>;
} // namespace FetiContact::QP
