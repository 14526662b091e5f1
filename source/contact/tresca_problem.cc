#include <feticontact/contact/contact_results.h>
#include <feticontact/contact/tresca_problem.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    /** Slip bounds below this fraction of the largest are zero (set_slip_bounds()). */
    constexpr double negligible_slip_bound = 1e-12;
  } // namespace

  void
  TrescaProblem::Statistics::count_steps(const QP::MPGP<DualVector>::Statistics &r)
  {
    cg_steps += r.cg_steps;
    expansion_steps += r.expansion_steps;
    proportioning_steps += r.proportioning_steps;
    expansion_fallbacks += r.expansion_fallbacks;
    recursive_gradient_updates += r.recursive_gradient_updates;
  }

  TrescaProblem::TrescaProblem(const DualProblem               &dual,
                               const DualLayout                &layout,
                               const std::vector<ContactNode>  &nodes,
                               const Parameters::ContactSolver &parameters,
                               std::ostream                    &out)
    : dual(dual)
    , layout(layout)
    , nodes(nodes)
    , parameters(parameters)
    , rows(dual)
    , block_t(rows.block(0, layout.n_tangential))
    , block_c(rows.block(layout.n_tangential, layout.size() - layout.n_tangential))
    , h(rows.h())
    , set(rows.n_local())
    , set_c(block_c.entries.size())
    , set_t(block_t.entries.size())
    , slip_bound(nodes.size(), 0.0)
  {
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        const unsigned int r = rows.local_index(layout.normal_row[k]);
        const unsigned int t = layout.tangential_row[k];
        local_normal_row.push_back(r);
        local_tangential_row.push_back(t == numbers::invalid_unsigned_int ? t :
                                                                            rows.local_index(t));
        AssertThrow(r != numbers::invalid_unsigned_int &&
                      (t == numbers::invalid_unsigned_int ||
                       local_tangential_row.back() != numbers::invalid_unsigned_int),
                    ExcMessage("TrescaProblem: this rank does not hold the rows of contact node " +
                               std::to_string(layout.node_number(k)) +
                               " (pass the nodes of hold_contact_nodes())."));
      }
    disc_of_node.assign(nodes.size(), numbers::invalid_unsigned_int);
    build_problems();
    build_constraint_sets();
    set_slip_bounds(slip_bound);
    estimate_scales(out);
  }

  void
  TrescaProblem::build_problems()
  {
    // Homogenization for the projector variant: Gλ₀ = e, h − Fλ₀, ẽ − G̃λ₀ = 0. λ₀ is taken
    // from the gluing and Dirichlet rows alone when they restrain the floating subdomains, else
    // from those and the normal rows, and only else from all rows (CoarseProblem::
    // particular_solution): the bounds are then λ̃_N ≥ 0 and the discs centred at the origin,
    // where radii far below ‖λ₀‖ (μ = 1e-8, nodes without contact) are resolved.
    unscaled.hessian     = [this](const DualVector &x, DualVector &y) { this->dual.apply_F(x, y); };
    unscaled.linear_term = h;
    unscaled.set         = &set;
    unscaled.G           = [this](const DualVector &x, Vector<double> &y) {
      this->dual.coarse.apply_G(x, y);
    };
    unscaled.Gt = [this](const Vector<double> &x, DualVector &y) {
      this->dual.coarse.apply_Gt(x, y);
    };
    unscaled.e = dual.e;
    QP::Orthonormalization<DualVector>::Factor factor;
    factor.solve_L = [this](Vector<double> &v) {
      this->dual.coarse.apply_orthonormalizing_factor(v, false);
    };
    factor.solve_Lt = [this](Vector<double> &v) {
      this->dual.coarse.apply_orthonormalizing_factor(v, true);
    };
    orthonormalization.emplace(unscaled, factor);
    original  = orthonormalization->transformed();
    problem   = original;
    lambda0   = rows.vector();
    projector = parameters.smalbe.equality_constraint ==
                  QP::SMALBEParameters::EqualityConstraint::projector &&
                dual.coarse.n_modes() > 0;
    if (projector)
      {
        homogenization.emplace(original, particular_solution(dual.e));
        lambda0     = homogenization->particular_solution();
        homogeneous = homogenization->transformed(set);
        projector_enforcement.emplace(homogeneous);
        problem = projector_enforcement->transformed();
      }
  }

  unsigned int
  TrescaProblem::tier(const unsigned int row) const
  {
    return row < layout.first_normal() ? 2 : row < layout.first_equality() ? 1 : 0;
  }

  DualVector
  TrescaProblem::particular_solution(const Vector<double> &e) const
  {
    const auto tier_of_row = [this](const unsigned int row) { return tier(row); };
    DualVector lambda;
    dual.coarse.particular_solution(e, tier_of_row, lambda);
    return lambda;
  }

  void
  TrescaProblem::build_constraint_sets()
  {
    for (unsigned int j = 0; j < nodes.size(); ++j)
      {
        const unsigned int r = local_normal_row[j];
        set.set_lower_bound(r, -lambda0.local_element(r));
        set_c.set_lower_bound(block_c.index_of(r), -lambda0.local_element(r));
        const unsigned int t = local_tangential_row[j];
        if (t == numbers::invalid_unsigned_int)
          continue;
        if (!layout.polygonal)
          {
            const std::array<double, 2> centre{
              {-lambda0.local_element(t), -lambda0.local_element(t + 1)}};
            disc_of_node[j] = set.add_disc(t, t + 1, centre, 0.0);
            set_t.add_disc(block_t.index_of(t), block_t.index_of(t + 1), centre, 0.0);
          }
      }
  }

  void
  TrescaProblem::estimate_scales(std::ostream &out)
  {
    // The equality constraint is used in the orthonormalized form G̃λ = ẽ (G̃G̃ᵀ = I), so ‖G̃‖ = 1.
    G_norm                 = dual.coarse.n_modes() > 0 ? 1.0 : 0.0;
    const DualVector start = rows.c();
    // The FETI part of the Hessian: F, or PFP in the projector variant. ‖F‖ bounds ‖PFP‖, but
    // with floating subdomains it also measures the local pseudo-inverses on the rigid body
    // modes, which P removes: with the projector SMALBE gets ‖PFP‖, the norm of the FETI part
    // of the Hessian it applies.
    if (parameters.penalty_projected_norm && projector)
      {
        DualVector Pv;
        feti_norm = 1.05 * QP::estimate_norm<DualVector>(
                             [&](const DualVector &x, DualVector &y) {
                               Pv = x;
                               apply_P(Pv);
                               dual.apply_F(Pv, y);
                               apply_P(y);
                             },
                             start,
                             projected_norm_iterations);
      }
    else
      feti_norm = 1.05 * QP::estimate_norm<DualVector>([&](const DualVector &x,
                                                           DualVector &y) { dual.apply_F(x, y); },
                                                       start,
                                                       10);
    rho = G_norm > 0 ? parameters.smalbe.penalty_factor * feti_norm / (G_norm * G_norm) : feti_norm;
    // ‖F + ρG̃ᵀG̃‖ ≤ ‖F‖ + ρ. In the projector variant the Hessian PFP + ρQ (Q = G̃ᵀG̃ = I − P) is
    // block diagonal in ker G̃ ⊕ range G̃ᵀ, so its norm is max(‖PFP‖, ρ) ≤ max(‖F‖, ρ).
    hessian_norm =
      parameters.smalbe.hessian_norm_bound == QP::SMALBEParameters::HessianNormBound::max &&
          projector ?
        std::max(feti_norm, rho * G_norm * G_norm) :
        feti_norm + rho * G_norm * G_norm;
    if (parameters.penalty_projected_norm && projector)
      out << "  Penalty: ρ = " << std::scientific << std::setprecision(3) << rho << " ("
          << parameters.smalbe.penalty_factor << " ‖PFP‖; ‖PFP‖ ≈ " << feti_norm << ")"
          << std::defaultfloat << std::endl;
    if (parameters.mpgp.arc_scale_estimate != QP::MPGPParameters::ArcScale::mean_diagonal)
      return;
    // tr(A)/m for A = PFP + ρQ (projector) or F + ρG̃ᵀG̃ (penalty): Hutchinson's estimate of
    // tr(PFP) = E[(Pv)ᵀF(Pv)] or tr(F), and exactly tr(ρG̃ᵀG̃) = ρ tr(G̃G̃ᵀ) = ρ × the number
    // of rigid modes (G̃ has orthonormal rows).
    const unsigned int m = layout.size();
    DualVector         Pv;
    const auto         PFP = [&](const DualVector &v, DualVector &y) {
      Pv = v;
      if (projector)
        apply_P(Pv);
      dual.apply_F(Pv, y);
    };
    arc_scale = QP::estimate_mean_diagonal<DualVector>(PFP, start, arc_scale_probes) +
                rho * G_norm * G_norm * dual.coarse.n_modes() / m;
    out << "  Arc preconditioner scale: mean diagonal of the Hessian " << std::scientific
        << std::setprecision(3) << arc_scale << " (" << arc_scale_probes
        << " probes), its norm bound " << hessian_norm << std::defaultfloat << std::endl;
  }

  void
  TrescaProblem::apply_P(DualVector &v) const
  {
    Vector<double> Gv;
    DualVector     Qv;
    dual.coarse.apply_G_orthonormal(v, Gv);
    dual.coarse.apply_Gt_orthonormal(Gv, Qv);
    v -= Qv;
  }

  void
  TrescaProblem::set_slip_bounds(const std::vector<double> &g)
  {
    slip_bound = g;
    // A slip bound below 1e-12 of the largest (compared as forces) comes from a normal force that
    // is zero to the solver's precision (the finest QP tolerance is 1e-10): its disc is a point.
    // As a disc of radius r it would stall MPGP, whose steps along the circle are limited by the
    // curvature 1/r (a radius of 4e-21 of the largest: 10,000 inner steps without progress).
    double largest = 0;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      if (std::isfinite(g[k]))
        largest = std::max(largest, g[k] * layout.scale_of_node(k));
    largest           = rows.max_over_ranks(largest);
    const auto radius = [&](const unsigned int k) {
      return g[k] * layout.scale_of_node(k) < negligible_slip_bound * largest ? 0. : g[k];
    };
    const unsigned int s      = layout.tangential_per_node;
    const double       shrink = std::sin(numbers::PI / (2.0 * s));
    for (unsigned int n = 0; n < nodes.size(); ++n)
      {
        const unsigned int t = local_tangential_row[n];
        if (t == numbers::invalid_unsigned_int)
          continue;
        const double r = radius(n);
        if (layout.polygonal)
          for (unsigned int j = 0; j < s; ++j)
            {
              const double c = lambda0.local_element(t + j);
              set.set_interval(t + j, -shrink * r - c, shrink * r - c);
              set_t.set_interval(block_t.index_of(t + j), -shrink * r - c, shrink * r - c);
            }
        else
          {
            set.set_disc_radius(disc_of_node[n], r);
            set_t.set_disc_radius(disc_of_node[n], r);
          }
      }
  }

  const std::vector<double> &
  TrescaProblem::slip_bounds() const
  {
    return slip_bound;
  }

  unsigned int
  TrescaProblem::n_equality_constraints() const
  {
    return original.e.size();
  }

  const TrescaProblem::Statistics &
  TrescaProblem::statistics() const
  {
    return counts;
  }

  DualVector
  TrescaProblem::total(const DualVector &lambda_tilde) const
  {
    DualVector lambda(lambda_tilde);
    lambda += lambda0;
    return lambda;
  }

  std::vector<double>
  TrescaProblem::normal_forces(const DualVector &lambda_tilde) const
  {
    // A node's multipliers are its forces / scale_of_node.
    std::vector<double> normal_force(nodes.size(), 0.0);
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        const unsigned int r = local_normal_row[k];
        normal_force[k] =
          layout.scale_of_node(k) * (lambda_tilde.local_element(r) + lambda0.local_element(r));
      }
    return normal_force;
  }

  double
  TrescaProblem::relative_change(const std::vector<double> &previous,
                                 const std::vector<double> &next) const
  {
    std::vector<ExactSum> sums(2); // ‖next − previous‖², ‖next‖²
    for (unsigned int k = 0; k < next.size(); ++k)
      {
        const double d = std::isfinite(previous[k]) ? next[k] - previous[k] : next[k];
        sums[0].add_product(d, d);
        sums[1].add_product(next[k], next[k]);
      }
    rows.sum_over_ranks(sums);
    const double difference = sums[0].value(), norm = sums[1].value();
    return norm > 0 ? std::sqrt(difference / norm) : 0.0;
  }

  QP::MPGP<DualVector>::AdditionalData
  TrescaProblem::mpgp_data() const
  {
    QP::MPGP<DualVector>::AdditionalData data = parameters.mpgp;
    data.step                                 = 1.9 / hessian_norm;
    data.arc_scale                            = arc_scale;
    return data;
  }

  QP::MPGP<DualVector>::Statistics
  TrescaProblem::solve_block(const QP::Operator<DualVector> &A,
                             const DualVector               &b,
                             DualVector                     &lambda,
                             const LocalDualRows::Block     &block,
                             const QP::SeparableSet         &block_set,
                             const double                    tolerance,
                             unsigned int                   &counter)
  {
    DualVector full(lambda), Afull(lambda), x = block.vector(), rhs = block.vector();
    block.extract(lambda, x);
    // b_block − A_{block, other} λ_other.
    for (const unsigned int i : block.entries)
      full.local_element(i) = 0;
    if (ReproducibleReductions::l2_norm(full) > 0)
      {
        A(full, Afull);
        ++counter;
      }
    else
      Afull = 0;
    block.extract(b, rhs);
    DualVector A_other = block.vector();
    block.extract(Afull, A_other);
    rhs -= A_other;
    // A restricted to the block: pad with zeros, multiply, extract.
    const QP::Operator<DualVector> A_block = [&](const DualVector &v, DualVector &y) {
      full = 0;
      block.insert(v, full);
      A(full, Afull);
      ++counter;
      block.extract(Afull, y);
    };
    QP::MPGP<DualVector>::AdditionalData data = mpgp_data();
    data.tolerance                            = tolerance;
    const auto report = QP::MPGP<DualVector>(data).solve(A_block, rhs, block_set, x);
    block.insert(x, lambda);
    counts.count_steps(report);
    return report;
  }

  QP::SolverReport
  TrescaProblem::gauss_seidel(const QP::Operator<DualVector> &A,
                              const DualVector               &b,
                              DualVector                     &lambda,
                              const double                    tolerance,
                              const MovingSet                *moving_set)
  {
    const unsigned int n_T = layout.n_tangential;
    QP::SolverReport   report;
    report.converged = true;
    // Each block to tolerance/2: when a sweep changes nothing, both block gradients are then
    // below it and ‖(g^P_c, g^P_t)‖ ≤ tolerance/√2; with `tolerance` itself per block the sweeps
    // could stall with the combined norm between tolerance and √2 tolerance.
    for (unsigned int sweep = 0; sweep < parameters.gauss_seidel_sweeps; ++sweep)
      {
        // λ_c = [λ_N; λ_E] by MPRGP with λ_T fixed.
        const auto rc = solve_block(A, b, lambda, block_c, set_c, tolerance / 2, counts.n_bound);
        report.iterations += rc.iterations;
        report.converged &= rc.converged;
        if (n_T == 0)
          break;
        if (moving_set)
          moving_set->update(lambda);
        // λ_T by KPG (MPGP on the discs) with λ_c fixed.
        const auto rt = solve_block(A, b, lambda, block_t, set_t, tolerance / 2, counts.n_disc);
        report.iterations += rt.iterations;
        report.converged &= rt.converged;
      }
    return report;
  }

  QP::SMALBE<DualVector>::InnerReport
  TrescaProblem::mpgp_inner_solve(const QP::Operator<DualVector> &A,
                                  const DualVector               &b,
                                  DualVector                     &x,
                                  const double                    tolerance,
                                  const DualVector               &gradient)
  {
    unsigned int                   calls   = 0;
    const QP::Operator<DualVector> counted = [&](const DualVector &v, DualVector &y) {
      A(v, y);
      ++calls;
    };
    QP::MPGP<DualVector>::AdditionalData data = mpgp_data();
    data.tolerance                            = tolerance;
    // MPGP starts from SMALBE's gradient and returns its own (no multiplication for either).
    DualVector g(gradient);
    const auto mpgp_report = QP::MPGP<DualVector>(data).solve(counted, b, set, x, &g);
    QP::SMALBE<DualVector>::InnerReport report(mpgp_report);
    report.capped = !mpgp_report.converged && mpgp_report.iterations >= data.max_iterations;
    counts.count_steps(mpgp_report);
    report.gradient.swap(g);
    counts.n_bound += calls;
    return report;
  }

  QP::SMALBE<DualVector>::Statistics
  TrescaProblem::solve(DualVector      &lambda,
                       Vector<double>  &nu,
                       const double     tolerance,
                       const Monitor   &monitor,
                       const MovingSet *moving_set)
  {
    QP::SMALBE<DualVector>::AdditionalData data = parameters.smalbe;
    data.tolerance                              = tolerance;
    data.feasibility_tolerance                  = tolerance;
    data.rho                                    = rho;
    data.F_norm                                 = feti_norm;
    data.G_norm                                 = G_norm;
    data.inner                                  = mpgp_data();
    if (moving_set)
      data.max_inner_calls = 1;
    const bool split = parameters.algorithm == Parameters::ContactSolver::Algorithm::algorithm_1 ||
                       parameters.algorithm == Parameters::ContactSolver::Algorithm::algorithm_2;
    DualVector             last_lambda;
    QP::SMALBE<DualVector> smalbe(data);
    if (split && layout.n_tangential > 0)
      smalbe.set_inner_solver([&](const QP::Operator<DualVector> &A,
                                  const DualVector               &b,
                                  DualVector                     &x,
                                  const double                    inner_tolerance,
                                  const DualVector & /*gradient*/) {
        QP::SMALBE<DualVector>::InnerReport r = gauss_seidel(A, b, x, inner_tolerance, moving_set);
        if (moving_set)
          {
            r.same_set  = moving_set->unchanged();
            r.final_set = moving_set->final();
          }
        last_lambda = x;
        return r;
      });
    else
      smalbe.set_inner_solver([&](const QP::Operator<DualVector> &A,
                                  const DualVector               &b,
                                  DualVector                     &x,
                                  const double                    inner_tolerance,
                                  const DualVector               &gradient) {
        QP::SMALBE<DualVector>::InnerReport r =
          mpgp_inner_solve(A, b, x, inner_tolerance, gradient);
        last_lambda = x;
        return r;
      });
    if (monitor)
      smalbe.set_monitor(
        [&](const QP::SMALBE<DualVector>::Step &step) { monitor(step, last_lambda); });
    const QP::SMALBE<DualVector>::Statistics report = smalbe.solve(problem, lambda, nu);
    counts.smalbe_iterations += report.iterations;
    return report;
  }

  void
  TrescaProblem::recover(DualVector &lambda, Vector<double> &nu) const
  {
    if (homogenization)
      homogenization->recover(lambda);
    // The equilibrium of the floating subdomains, Gλ = e, holds after SMALBE to its feasibility
    // tolerance only; restore it to rounding with a correction from the gluing rows (the same
    // choice of rows as for λ₀), which leaves the contact multipliers as solved.
    if (dual.coarse.n_modes() > 0)
      {
        Vector<double> misfit(dual.e), G_lambda;
        dual.coarse.apply_G(lambda, G_lambda);
        misfit -= G_lambda;
        lambda += particular_solution(misfit);
      }
    if (projector_enforcement)
      {
        // The multiplier of the original problem from that of the projected one.
        DualVector r = rows.vector();
        dual.apply_F(lambda, r);
        r -= h;
        projector_enforcement->recover_multiplier(r, nu);
      }
    nu = orthonormalization->recover_multiplier(nu);
  }

  std::array<unsigned int, 3>
  TrescaProblem::status_counts(const DualVector &lambda_tilde) const
  {
    const DualVector          lambda = total(lambda_tilde);
    std::vector<unsigned int> counts_by_status(3, 0);
    // The normal force σ_k λ_N (σ_k ≠ 1 only with averaged contact rows) against the largest;
    // slip and stick compare multipliers of the same node.
    double lambda_max = 0;
    for (unsigned int k = 0; k < nodes.size(); ++k)
      lambda_max =
        std::max(lambda_max, layout.scale_of_node(k) * lambda.local_element(local_normal_row[k]));
    lambda_max = rows.max_over_ranks(lambda_max);
    for (unsigned int k = 0; k < nodes.size(); ++k)
      {
        const double       lN = layout.scale_of_node(k) * lambda.local_element(local_normal_row[k]);
        const unsigned int t  = local_tangential_row[k];
        double             lT = 0;
        if (t != numbers::invalid_unsigned_int)
          for (unsigned int j = 0; j < layout.tangential_per_node; ++j)
            lT += lambda.local_element(t + j) * lambda.local_element(t + j);
        const ContactStatus status =
          contact_status(is_pressed(lN, lambda_max),
                         std::sqrt(lT),
                         t == numbers::invalid_unsigned_int ? 0. : slip_bound[k]);
        ++counts_by_status[static_cast<unsigned int>(status)];
      }
    rows.sum_over_ranks(counts_by_status);
    return {{counts_by_status[0], counts_by_status[1], counts_by_status[2]}};
  }

  std::string
  TrescaProblem::no_equilibrium_message(const QP::SMALBE<DualVector>::Statistics &report) const
  {
    // The certificate in the original variables: with the projector SMALBE saw λ̃ ∈ Ω − λ₀ and
    // G̃λ̃ = 0, so αᵀẽ = αᵀG̃λ₀ and σ_Ω = σ_{Ω−λ₀} + αᵀG̃λ₀.
    double work = report.certificate_work, support = report.certificate_support;
    if (projector)
      {
        Vector<double> e_tilde(dual.coarse.n_modes());
        dual.coarse.apply_G_orthonormal(lambda0, e_tilde);
        work = report.certificate * e_tilde;
        support += work;
      }
    std::ostringstream text;
    text << "no equilibrium: the contact forces allowed by the current bounds (λ_N ≥ 0, "
            "‖λ_T‖ ≤ slip bound) cannot balance the loads on the floating subdomains. On a "
            "rigid motion α of those subdomains the loads do the work "
         << work << ", the contact forces at most " << support
         << " (a proof: no multiplier within the bounds satisfies Gλ = e). For a body held "
            "only by contact: the tangential loads exceed the friction coefficient times "
            "the normal force (full sliding), or the loads pull the body off the obstacle";
    return text.str();
  }

} // namespace FetiContact
