// SMALBE-M on small problems with known solutions: min ½xᵀAx − bᵀx s.t. x ∈ Ω, Gx = e. Built
// from a chosen KKT point as in qp_mpgp.cc (A SPD with condition number 1e3, Ω with intervals,
// lower bounds, free components and discs, x* and g* satisfying the KKT conditions of Ω) plus a
// random G (k × n, full row rank) and multiplier μ*: e = Gx*, b = Ax* + Gᵀμ* − g*. With enough
// free components (G restricted to them has full rank) x* and μ* are unique. Checked: x and μ,
// Gx = e, the KKT conditions of x with the returned μ (by a projection written here), and that the
// report counts every multiplication by the inner Hessian. Cases: generic mix; e = 0; data scaled
// by 2^∓37 (bit for bit the same x, same counts) and by 1e-11 and 1e11 (same x), μ scaled; a
// user-supplied inner solver. The QP vectors are DistributedVector on one process (global index =
// local index), the vectors of G's range (μ, e) dealii::Vector<double>.

#include <deal.II/base/mpi.h>
#include <deal.II/lac/full_matrix.h>

#include <feticontact/base/reproducible_partitioner.h>
#include <feticontact/qp/mpgp.h>
#include <feticontact/qp/separable_set.h>
#include <feticontact/qp/smalbe.h>
#include <feticontact/qp/transforms.h>

#include "qp_test_problems.h"
#include "test_tools.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using namespace dealii;
using namespace FetiContact;

namespace
{
  using namespace QPTestProblems;

  enum class Role
  {
    free,
    interval_inside,
    interval_lower,
    interval_upper,
    interval_fixed,
    lower_inside,
    lower_active,
    upper_active,
    disc_inside,
    disc_centre,
    disc_active,
    disc_degenerate,
    disc_fixed
  };

  bool
  is_disc(const Role role)
  {
    return role == Role::disc_inside || role == Role::disc_centre || role == Role::disc_active ||
           role == Role::disc_degenerate || role == Role::disc_fixed;
  }

  struct Block
  {
    Role         role;
    unsigned int i, j;
    double       l = -infinity, u = infinity;
    double       c1 = 0, c2 = 0, r = 0;
  };

  struct Problem
  {
    unsigned int       n = 0;
    FullMatrix<double> A;
    DistributedVector  b, x_star, g_star;
    std::vector<Block> blocks;
    QP::SeparableSet   set{0};
    double             A_norm = 0;
    FullMatrix<double> G;
    Vector<double>     e, mu_star;
  };

  /** A problem with `count` blocks of each role, components in random order. */
  Problem
  make_problem(const std::vector<std::pair<Role, unsigned int>> &roles,
               const double                                      condition = 1e3)
  {
    Problem problem;
    for (const auto &[role, count] : roles)
      problem.n += count * (is_disc(role) ? 2 : 1);
    const unsigned int        n = problem.n;
    std::vector<unsigned int> permutation(n);
    for (unsigned int i = 0; i < n; ++i)
      permutation[i] = i;
    std::shuffle(permutation.begin(), permutation.end(), random_engine);
    problem.x_star.reinit(n);
    problem.g_star.reinit(n);
    problem.set             = QP::SeparableSet(n);
    unsigned int       next = 0;
    DistributedVector &x = problem.x_star, &g = problem.g_star;
    for (const auto &[role, count] : roles)
      for (unsigned int c = 0; c < count; ++c)
        {
          Block block;
          block.role           = role;
          block.i              = permutation[next++];
          block.j              = is_disc(role) ? permutation[next++] : block.i;
          const unsigned int i = block.i, j = block.j;
          const double       l = random_in(-2, 1), u = l + random_in(0.5, 2);
          const double       theta = random_in(0, 2 * M_PI);
          const double       n1 = std::cos(theta), n2 = std::sin(theta);
          if (is_disc(role))
            {
              block.c1 = random_in(-1, 1);
              block.c2 = random_in(-1, 1);
              block.r  = role == Role::disc_fixed ? 0. : random_in(0.5, 2);
            }
          switch (role)
            {
              case Role::free:
                x[i] = random_in(-2, 2);
                break;
              case Role::interval_inside:
                block.l = l, block.u = u, x[i] = random_in(l + 0.1 * (u - l), u - 0.1 * (u - l));
                break;
              case Role::interval_lower:
                block.l = l, block.u = u, x[i] = l, g[i] = random_in(0.5, 1.5);
                break;
              case Role::interval_upper:
                block.l = l, block.u = u, x[i] = u, g[i] = -random_in(0.5, 1.5);
                break;
              case Role::interval_fixed:
                block.l = block.u = l, x[i] = l, g[i] = random_in(-1.5, 1.5);
                break;
              case Role::lower_inside:
                block.l = l, x[i] = l + random_in(0.2, 1.5);
                break;
              case Role::lower_active:
                block.l = l, x[i] = l, g[i] = random_in(0.5, 1.5);
                break;
              case Role::upper_active:
                block.u = u, x[i] = u, g[i] = -random_in(0.5, 1.5);
                break;
                case Role::disc_inside: {
                  const double s = random_in(0.2, 0.8) * block.r;
                  x[i] = block.c1 + s * n1, x[j] = block.c2 + s * n2;
                  break;
                }
              case Role::disc_centre:
                x[i] = block.c1, x[j] = block.c2;
                break;
              case Role::disc_active:
                case Role::disc_degenerate: {
                  x[i] = block.c1 + block.r * n1, x[j] = block.c2 + block.r * n2;
                  const double sigma = role == Role::disc_active ? random_in(0.5, 1.5) : 0.;
                  g[i] = -sigma * n1, g[j] = -sigma * n2;
                  break;
                }
              case Role::disc_fixed:
                x[i] = block.c1, x[j] = block.c2;
                g[i] = random_in(-1.5, 1.5), g[j] = random_in(-1.5, 1.5);
                break;
            }
          if (is_disc(role))
            problem.set.add_disc(i, j, {{block.c1, block.c2}}, block.r);
          else if (role != Role::free)
            problem.set.set_interval(i, block.l, block.u);
          problem.blocks.push_back(block);
        }
    problem.A      = random_spd(n, condition);
    problem.A_norm = condition;
    problem.b.reinit(n);
    multiply(problem.A, x, problem.b);
    problem.b -= g;
    return problem;
  }

  /** The projection onto one block, written independently of SeparableSet. */
  void
  project_block(const Block &block, DistributedVector &x)
  {
    if (is_disc(block.role))
      {
        const double y1 = x[block.i] - block.c1, y2 = x[block.j] - block.c2;
        const double d = std::sqrt(y1 * y1 + y2 * y2);
        if (d > block.r)
          x[block.i] = block.c1 + block.r * y1 / d, x[block.j] = block.c2 + block.r * y2 / d;
      }
    else
      x[block.i] = std::min(std::max(x[block.i], block.l), block.u);
  }

  double
  violation(const Problem &problem, const DistributedVector &x)
  {
    double v = 0;
    for (const Block &block : problem.blocks)
      if (is_disc(block.role))
        v = std::max(v, std::hypot(x[block.i] - block.c1, x[block.j] - block.c2) - block.r);
      else
        v = std::max({v, block.l - x[block.i], x[block.i] - block.u});
    return v;
  }

  /** ‖x − P_Ω(x − t g)‖/t with t = 1/‖A‖: zero exactly at a KKT point. */
  double
  kkt_residual(const Problem &problem, const DistributedVector &x, const DistributedVector &g)
  {
    const double      t = 1 / problem.A_norm;
    DistributedVector y(x);
    y.add(-t, g);
    for (const Block &block : problem.blocks)
      project_block(block, y);
    y -= x;
    return y.l2_norm() / t;
  }

  /** Adds G (k × n, random) and μ*: e = Gx* (or G made orthogonal to x* for e = 0),
   * b = Ax* + Gᵀμ* − g*. */
  void
  add_equalities(Problem           &p,
                 const unsigned int k,
                 const bool         homogeneous,
                 const bool         orthonormal = false)
  {
    p.G.reinit(k, p.n);
    for (unsigned int i = 0; i < k; ++i)
      for (unsigned int j = 0; j < p.n; ++j)
        p.G(i, j) = uniform(random_engine);
    if (homogeneous)
      {
        // G ← G − (Gx*) x*ᵀ/‖x*‖²: then Gx* = 0.
        Vector<double> Gx(k);
        multiply(p.G, p.x_star, Gx);
        const double xx = p.x_star.norm_sqr();
        for (unsigned int i = 0; i < k; ++i)
          for (unsigned int j = 0; j < p.n; ++j)
            p.G(i, j) -= Gx[i] * p.x_star[j] / xx;
      }
    if (orthonormal)
      // Gram–Schmidt on the rows (the row space, hence Gx* = 0, is kept): GGᵀ = I.
      for (unsigned int i = 0; i < k; ++i)
        {
          for (unsigned int l = 0; l < i; ++l)
            {
              double dot = 0;
              for (unsigned int j = 0; j < p.n; ++j)
                dot += p.G(i, j) * p.G(l, j);
              for (unsigned int j = 0; j < p.n; ++j)
                p.G(i, j) -= dot * p.G(l, j);
            }
          double norm = 0;
          for (unsigned int j = 0; j < p.n; ++j)
            norm += p.G(i, j) * p.G(i, j);
          for (unsigned int j = 0; j < p.n; ++j)
            p.G(i, j) /= std::sqrt(norm);
        }
    p.e.reinit(k);
    multiply(p.G, p.x_star, p.e);
    if (homogeneous)
      p.e = 0;
    p.mu_star.reinit(k);
    for (auto &v : p.mu_star)
      v = 10 * uniform(random_engine);
    DistributedVector Gtmu(p.n);
    multiply_transposed(p.G, p.mu_star, Gtmu);
    p.b += Gtmu;
  }

  struct Result
  {
    DistributedVector                         x;
    Vector<double>                            mu;
    QP::SMALBE<DistributedVector>::Statistics report;
  };

  /** Solves the problem with F, h scaled by s and checks the solution. */
  Result
  solve_and_check(
    const std::string                                &name,
    const Problem                                    &problem,
    const double                                      s                                   = 1,
    const QP::SMALBE<DistributedVector>::InnerSolver &inner_solver                        = {},
    unsigned int                                     *operator_calls                      = nullptr,
    const double                                      tolerance                           = 1e-12,
    const bool                                        projector                           = false,
    const std::function<void(QP::SMALBE<DistributedVector>::AdditionalData &)> &configure = {})
  {
    std::cout << name << (projector ? ", projector variant" : "") << " (n = " << problem.n
              << ", k = " << problem.G.m() << ", scale " << s << ", ε " << tolerance << ")"
              << std::endl;
    unsigned int F_count = 0;
    const auto   F       = [&](const DistributedVector &v, DistributedVector &w) {
      multiply(problem.A, v, w);
      w *= s;
      ++F_count;
    };
    const auto G = [&](const DistributedVector &v, Vector<double> &w) {
      multiply(problem.G, v, w);
    };
    const auto Gt = [&](const Vector<double> &v, DistributedVector &w) {
      multiply_transposed(problem.G, v, w);
    };
    DistributedVector h(problem.b);
    h *= s;
    QP::SMALBE<DistributedVector>::AdditionalData options;
    options.tolerance             = tolerance;
    options.feasibility_tolerance = tolerance;
    unsigned int outer_monitored  = 0;
    const auto   monitor          = [&](const QP::SMALBE<DistributedVector>::Step &step) {
      ++outer_monitored;
      std::cout << "    outer " << step.outer_iteration << ": inner " << step.inner_iterations
                << " steps/" << step.inner_calls << " calls, n_A = " << step.hessian_multiplications
                << ", ‖g^P‖ rel " << sci(step.relative_gradient) << ", ‖Gλ − e‖ rel "
                << sci(step.relative_feasibility) << ", M " << sci(step.M)
                << (step.M_decreased ? " (decreased)" : "") << std::endl;
    };
    if (configure)
      configure(options);
    QP::SMALBE<DistributedVector> smalbe(options);
    if (inner_solver)
      smalbe.set_inner_solver(inner_solver);
    smalbe.set_monitor(monitor);
    QP::Problem<DistributedVector> qp;
    qp.hessian     = F;
    qp.linear_term = h;
    qp.set         = &problem.set;
    qp.G           = G;
    qp.Gt          = Gt;
    qp.e           = problem.e;
    Result result;
    result.x.reinit(problem.n);
    if (projector)
      result.report = smalbe.solve(QP::ProjectorEnforcement<DistributedVector>(qp).transformed(),
                                   result.x,
                                   result.mu);
    else
      result.report = smalbe.solve(qp, result.x, result.mu);
    const auto &r = result.report;
    check(r.converged,
          "converged: " + std::to_string(r.iterations) + " outer iterations, " +
            std::to_string(r.inner_iterations) + " inner steps in " +
            std::to_string(r.inner_calls) + " calls, " + std::to_string(r.hessian_multiplications) +
            " multiplications by F + ρGᵀG, ‖g^P‖ rel " + sci(r.relative_gradient) +
            ", ‖Gλ − e‖ rel " + sci(r.relative_feasibility));
    check(outer_monitored == r.iterations, "monitor called once per outer iteration");
    check(F_count == r.hessian_multiplications + r.norm_estimate_multiplications,
          "multiplications counted exactly (" + std::to_string(F_count) +
            " by F = " + std::to_string(r.hessian_multiplications) + " Hessian + " +
            std::to_string(r.norm_estimate_multiplications) + " for ‖F‖)");
    if (operator_calls)
      *operator_calls = F_count;
    DistributedVector error(result.x);
    error -= problem.x_star;
    check(error.l2_norm() <= 1e4 * tolerance * problem.x_star.l2_norm(),
          "‖x − x*‖/‖x*‖ = " + sci(error.l2_norm() / problem.x_star.l2_norm()));
    Vector<double> mu_error(result.mu);
    if (projector)
      {
        // The multiplier of the original problem: μ − G(Fλ − h).
        DistributedVector r(problem.n);
        Vector<double>    Gr(problem.G.m());
        F(result.x, r);
        --F_count;
        r -= h;
        multiply(problem.G, r, Gr);
        mu_error -= Gr;
        result.mu = mu_error;
      }
    mu_error /= s;
    mu_error -= problem.mu_star;
    check(mu_error.l2_norm() <= 1e-6 * problem.mu_star.l2_norm() &&
            (projector || result.mu == r.mu),
          "‖μ/s − μ*‖/‖μ*‖ = " + sci(mu_error.l2_norm() / problem.mu_star.l2_norm()));
    const double v = violation(problem, result.x);
    check(v <= 1e-14 * std::max(1., result.x.linfty_norm()),
          "x ∈ Ω (largest violation " + sci(v) + ")");
    Vector<double> Gx(problem.G.m());
    multiply(problem.G, result.x, Gx);
    Gx -= problem.e;
    const double e_scale = problem.e.l2_norm() > 0 ? problem.e.l2_norm() : result.x.l2_norm();
    check(Gx.l2_norm() <= 10 * tolerance * e_scale,
          "‖Gx − e‖/scale = " + sci(Gx.l2_norm() / e_scale));
    // KKT: g = Ax − b + Gᵀμ (unscaled) in −N_Ω(x).
    DistributedVector g(problem.n), Gtmu(problem.n);
    multiply(problem.A, result.x, g);
    g -= problem.b;
    multiply_transposed(problem.G, result.mu, Gtmu);
    g.add(1 / s, Gtmu);
    const double kkt = kkt_residual(problem, result.x, g);
    check(kkt <= 1e3 * tolerance * problem.b.l2_norm(),
          "KKT: ‖x − P(x − g/‖A‖)‖‖A‖/‖b‖ = " + sci(kkt / problem.b.l2_norm()));
    return result;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  using R = Role;
  const std::vector<std::pair<Role, unsigned int>> roles{{R::free, 8},
                                                         {R::interval_inside, 3},
                                                         {R::interval_lower, 3},
                                                         {R::interval_upper, 2},
                                                         {R::lower_inside, 3},
                                                         {R::lower_active, 4},
                                                         {R::upper_active, 1},
                                                         {R::disc_inside, 2},
                                                         {R::disc_centre, 1},
                                                         {R::disc_active, 4},
                                                         {R::disc_degenerate, 1},
                                                         {R::disc_fixed, 1}};
  Problem                                          mix = make_problem(roles);
  add_equalities(mix, 5, false);
  solve_and_check("generic mix", mix);

  // F and h scaled against the unscaled problem. By 2^∓37 (about 7e-12 and 1.4e11), solved to
  // ε = 1e-10, floating-point arithmetic scales exactly, so any absolute threshold in SMALBE or
  // MPGP would show as a different path: the same counts and bit for bit the same x are
  // required. By 1e-11 and 1e11 the rounding differs and decisions taken on gradients near the
  // tolerance can differ by a step, so both are solved to ε = 1e-12: the same x to 1e-9.
  // μ scales with F in both.
  {
    const Result reference = solve_and_check("generic mix", mix, 1, {}, nullptr, 1e-10);
    const Result tight     = solve_and_check("generic mix", mix, 1, {}, nullptr, 1e-12);
    for (const double s : {std::ldexp(1., -37), std::ldexp(1., 37), 1e-11, 1e11})
      {
        const bool   exact = s == std::ldexp(1., -37) || s == std::ldexp(1., 37);
        const Result r =
          solve_and_check("generic mix, scaled", mix, s, {}, nullptr, exact ? 1e-10 : 1e-12);
        DistributedVector d(r.x);
        d -= exact ? reference.x : tight.x;
        check(d.l2_norm() <= (exact ? 0. : 1e-9) * reference.x.l2_norm(),
              std::string(exact ? "bit for bit " : "") +
                "the same x as unscaled: " + sci(d.l2_norm() / reference.x.l2_norm()));
        if (exact)
          check(r.report.iterations == reference.report.iterations &&
                  r.report.hessian_multiplications == reference.report.hessian_multiplications,
                "same counts as unscaled (" + std::to_string(r.report.iterations) + " outer, " +
                  std::to_string(r.report.hessian_multiplications) + " multiplications)");
      }
  }

  {
    Problem p = make_problem(roles);
    add_equalities(p, 6, true);
    solve_and_check("e = 0", p);
  }

  {
    // The projector variant (PFP + ρQ, P = I − GᵀG) needs e = 0 and GGᵀ = I: the solution and
    // the multiplier (μ − G(Fλ − h)) of the original problem, checked by solve_and_check.
    Problem p = make_problem(roles);
    add_equalities(p, 6, true, true);
    solve_and_check("e = 0, orthonormal G", p);
    solve_and_check("e = 0, orthonormal G", p, 1, {}, nullptr, 1e-12, true);
    bool refused = false;
    try
      {
        Problem           q = make_problem(roles);
        DistributedVector x(q.n);
        Vector<double>    mu;
        add_equalities(q, 3, false, true);
        QP::Problem<DistributedVector> qp;
        qp.hessian = [&](const DistributedVector &v, DistributedVector &w) { multiply(q.A, v, w); };
        qp.linear_term = q.b;
        qp.set         = &q.set;
        qp.G  = [&](const DistributedVector &v, Vector<double> &w) { multiply(q.G, v, w); };
        qp.Gt = [&](const Vector<double> &v, DistributedVector &w) {
          multiply_transposed(q.G, v, w);
        };
        qp.e = q.e;
        QP::ProjectorEnforcement<DistributedVector> projector(qp);
        QP::SMALBE<DistributedVector>().solve(projector.transformed(), x, mu);
      }
    catch (const std::exception &)
      {
        refused = true;
      }
    check(refused, "projector variant with e ≠ 0 is refused");
  }

  {
    // InnerReport::same_set: an inner solver that changes the set while it solves (Algorithm 2
    // moves the radii) reports whether the set is that of the previous call. "Yes" is the
    // default path; "no" keeps M at M_0 (the M test compares Lagrangians over different sets),
    // and SMALBE still converges here.
    const auto plug = [&](const bool same_set) -> QP::SMALBE<DistributedVector>::InnerSolver {
      return [&, same_set](const QP::Operator<DistributedVector> &A,
                           const DistributedVector               &b,
                           DistributedVector                     &x,
                           const double                           tolerance,
                           const DistributedVector               &gradient)
               -> QP::SMALBE<DistributedVector>::InnerReport {
        QP::MPGP<DistributedVector>::AdditionalData options;
        options.tolerance = tolerance;
        DistributedVector                          g(gradient);
        QP::SMALBE<DistributedVector>::InnerReport report(
          QP::MPGP<DistributedVector>(options).solve(A, b, mix.set, x, &g));
        report.gradient.swap(g);
        report.same_set = same_set;
        return report;
      };
    };
    const Result reference = solve_and_check("generic mix, same set", mix, 1, plug(true));
    const Result changed =
      solve_and_check("generic mix, set reported changed", mix, 1, plug(false));
    check(reference.report.M < changed.report.M,
          "same_set = false: M stays at M_0 = " + sci(changed.report.M) +
            " (with the same set: " + sci(reference.report.M) + ")");
  }

  {
    // The plug: an inner solver of our own (MPGP with Γ = 2 and ᾱ from a power method on the
    // inner operator), counting its calls.
    unsigned int                                     inner_calls = 0;
    const QP::SMALBE<DistributedVector>::InnerSolver inner =
      [&](const QP::Operator<DistributedVector> &A,
          const DistributedVector               &b,
          DistributedVector                     &x,
          const double                           tolerance,
          const DistributedVector & /*gradient*/) -> QP::SolverReport {
      ++inner_calls;
      QP::MPGP<DistributedVector>::AdditionalData options;
      options.tolerance = tolerance;
      options.gamma     = 2;
      return QP::MPGP<DistributedVector>(options).solve(A, b, mix.set, x);
    };
    unsigned int calls = 0;
    const Result r     = solve_and_check("user-supplied inner solver", mix, 1, inner, &calls);
    check(inner_calls == r.report.inner_calls && inner_calls >= r.report.iterations,
          "the user's solver did the inner solves (" + std::to_string(inner_calls) + " calls)");
  }
  {
    // The gradient passed between the inner solves: an inner solver that starts from SMALBE's
    // gradient and returns its own saves the multiplication at its start and SMALBE's after it.
    const auto plug = [&](const bool pass_gradient) -> QP::SMALBE<DistributedVector>::InnerSolver {
      return [&, pass_gradient](const QP::Operator<DistributedVector> &A,
                                const DistributedVector               &b,
                                DistributedVector                     &x,
                                const double                           tolerance,
                                const DistributedVector               &gradient)
               -> QP::SMALBE<DistributedVector>::InnerReport {
        QP::MPGP<DistributedVector>::AdditionalData options;
        options.tolerance = tolerance;
        if (!pass_gradient)
          return QP::MPGP<DistributedVector>(options).solve(A, b, mix.set, x);
        DistributedVector                          g(gradient);
        QP::SMALBE<DistributedVector>::InnerReport report(
          QP::MPGP<DistributedVector>(options).solve(A, b, mix.set, x, &g));
        report.gradient.swap(g);
        return report;
      };
    };
    unsigned int calls_without = 0, calls_with = 0;
    const Result without =
      solve_and_check("inner solver without the gradient", mix, 1, plug(false), &calls_without);
    const Result with =
      solve_and_check("inner solver with the gradient", mix, 1, plug(true), &calls_with);
    check(calls_with + with.report.inner_calls <= calls_without,
          "passing the gradient saves at least one multiplication per inner solve (" +
            std::to_string(calls_with) + " against " + std::to_string(calls_without) +
            " multiplications, " + std::to_string(with.report.inner_calls) + " inner solves)");
  }
  std::cout << (n_failures == 0 ? "PASSED" : "FAILED") << std::endl;
  return n_failures;
}
