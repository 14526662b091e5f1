// SeparableSet and MPGP on small problems with known solutions. Each problem is built from a
// chosen KKT point: A SPD (n ≈ 30–60, condition number 1e3), blocks of every kind (free,
// intervals, lower bounds, discs), x* and g* with g* = 0 on free and interior blocks, g*_i > 0 at
// an active lower end, < 0 at an active upper end, g* = −σν (σ > 0) on an active disc, anything
// on fixed blocks; then b = Ax* − g*. A is SPD, so x* is the unique minimizer. Checked: ‖x − x*‖,
// feasibility and the KKT conditions of the computed x (by a projection written here, not the
// SeparableSet's), the gradient against g* (the multipliers), and that every multiplication by
// A is counted. Cases: generic mix; solution at disc centres; on a disc boundary with zero
// gradient; all constraints active; none active (= the unconstrained solution); zero-radius
// discs; bounds only (MPRGP); data scaled by 2^∓37 (bit for bit the same x, same counts) and by
// 1e-11 and 1e11 (same x); a start outside Ω; preconditioning in face (every case, and a badly
// scaled problem where it must save multiplications). The QP vectors are DistributedVector on one
// process (global index = local index).

#include <deal.II/base/mpi.h>
#include <deal.II/lac/full_matrix.h>

#include <feticontact/base/reproducible_partitioner.h>
#include <feticontact/qp/mpgp.h>
#include <feticontact/qp/separable_set.h>

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
    disc_curved,
    disc_degenerate,
    disc_fixed
  };

  bool
  is_disc(const Role role)
  {
    return role == Role::disc_inside || role == Role::disc_centre || role == Role::disc_active ||
           role == Role::disc_curved || role == Role::disc_degenerate || role == Role::disc_fixed;
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
              block.r  = role == Role::disc_fixed  ? 0. :
                         role == Role::disc_curved ? random_in(1e-4, 1e-3) :
                                                     random_in(0.5, 2);
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
              case Role::disc_curved:
                case Role::disc_degenerate: {
                  x[i] = block.c1 + block.r * n1, x[j] = block.c2 + block.r * n2;
                  const double sigma = role == Role::disc_degenerate ? 0. : random_in(0.5, 1.5);
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

  struct Result
  {
    DistributedVector                       x;
    QP::MPGP<DistributedVector>::Statistics report;
  };

  /** The variants of MPGP on discs (MPGP::AdditionalData::disc_rotations,
   * proportioning_line_search). */
  enum class Variant
  {
    /** The default: rotations along active discs. */
    rotations,
    /** Fixed active discs (Dostál–Kozubek, KPG), proportioning step from the arc model. */
    fixed_discs,
    /** Fixed active discs with the fixed step ᾱ in projected proportioning steps. */
    fixed_step,
    /** Rotations, and expansion by the projected conjugate gradient step. */
    projected_cg,
    /** Rotations, conjugate gradient steps preconditioned in face by diag(A)⁻¹. */
    preconditioned,
    /** Rotations, the gradient after steps along the circles updated recursively (η = 0.1). */
    recursive_arcs,
    /** Rotations, the arc preconditioner scaled by the mean diagonal tr(A)/n, not by ‖A‖. */
    mean_diagonal_arcs
  };

  std::string
  variant_name(const Variant variant)
  {
    switch (variant)
      {
        case Variant::rotations:
          return "";
        case Variant::fixed_discs:
          return ", fixed discs";
        case Variant::projected_cg:
          return ", projected CG expansion";
        case Variant::preconditioned:
          return ", preconditioned in face";
        case Variant::recursive_arcs:
          return ", recursive gradient along the circles";
        case Variant::mean_diagonal_arcs:
          return ", arc preconditioner scaled by the mean diagonal";
        default:
          return ", fixed discs, fixed-step proportioning";
      }
  }

  /** Solves the problem scaled by s (A and b times s) from x0 and checks the solution. */
  Result
  solve_and_check(const std::string       &name,
                  const Problem           &problem,
                  const DistributedVector &x0,
                  const double             s         = 1,
                  const Variant            variant   = Variant::rotations,
                  const double             tolerance = 1e-12)
  {
    std::cout << name << variant_name(variant) << " (n = " << problem.n << ", scale " << s << ")"
              << std::endl;
    unsigned int count = 0;
    const auto   A     = [&](const DistributedVector &v, DistributedVector &w) {
      multiply(problem.A, v, w);
      w *= s;
      ++count;
    };
    DistributedVector b(problem.b);
    b *= s;
    QP::MPGP<DistributedVector>::AdditionalData options;
    options.tolerance      = tolerance * QP::l2_norm(b);
    options.disc_rotations = variant != Variant::fixed_discs && variant != Variant::fixed_step;
    if (variant == Variant::preconditioned)
      options.preconditioner = [&](const DistributedVector &v, DistributedVector &w) {
        w.reinit(v, true);
        for (unsigned int i = 0; i < v.locally_owned_size(); ++i)
          w.local_element(i) = v.local_element(i) / (s * problem.A(i, i));
      };
    options.expansion                 = variant == Variant::projected_cg ?
                                          QP::MPGP<DistributedVector>::AdditionalData::Expansion::projected_cg :
                                          QP::MPGP<DistributedVector>::AdditionalData::Expansion::fixed_step;
    options.proportioning_line_search = variant != Variant::fixed_step;
    if (variant == Variant::recursive_arcs)
      options.recursive_gradient_tolerance = 0.1;
    if (variant == Variant::mean_diagonal_arcs)
      {
        double trace = 0;
        for (unsigned int i = 0; i < problem.n; ++i)
          trace += problem.A(i, i);
        options.arc_scale = s * trace / problem.n;
      }
    Result result;
    result.x      = x0;
    result.report = QP::MPGP<DistributedVector>(options).solve(A, b, problem.set, result.x);
    const auto &r = result.report;
    check(r.converged,
          "converged: " + std::to_string(r.iterations) + " steps (" + std::to_string(r.cg_steps) +
            " CG, " + std::to_string(r.expansion_steps) + " expansion, " +
            std::to_string(r.proportioning_steps) + " proportioning, " +
            std::to_string(r.proportioning_fallbacks) + " fallbacks), " +
            std::to_string(r.hessian_multiplications) +
            " multiplications by A, ‖g^P‖/‖b‖ = " + sci(r.relative_residual));
    check(count == r.hessian_multiplications,
          "multiplications counted exactly (" + std::to_string(count) + ")");
    DistributedVector error(result.x);
    error -= problem.x_star;
    check(error.l2_norm() <= 1e4 * tolerance * problem.x_star.l2_norm(),
          "‖x − x*‖/‖x*‖ = " + sci(error.l2_norm() / problem.x_star.l2_norm()));
    const double v = violation(problem, result.x);
    check(v <= 1e-14 * std::max(1., result.x.linfty_norm()) &&
            problem.set.is_feasible(result.x, 1e-14),
          "feasible (largest violation " + sci(v) + ")");
    DistributedVector g(problem.n);
    multiply(problem.A, result.x, g);
    g -= problem.b; // unscaled gradient
    const double kkt = kkt_residual(problem, result.x, g);
    check(kkt <= 1e2 * tolerance * problem.b.l2_norm(),
          "KKT: ‖x − P(x − g/‖A‖)‖‖A‖/‖b‖ = " + sci(kkt / problem.b.l2_norm()));
    g -= problem.g_star;
    check(g.l2_norm() <= 1e5 * tolerance * problem.b.l2_norm(),
          "multipliers: ‖g − g*‖/‖b‖ = " + sci(g.l2_norm() / problem.b.l2_norm()));
    return result;
  }

  void
  check_set()
  {
    std::cout << "SeparableSet" << std::endl;
    QP::SeparableSet set(7);
    set.set_interval(0, 0, 1);
    set.set_lower_bound(1, 1);
    const unsigned int k0 = set.add_disc(2, 3, {{0, 0}}, 1);
    const unsigned int k1 = set.add_disc(4, 5, {{1, 2}}, 0);
    check(k0 == 0 && k1 == 1 && set.n_discs() == 2, "disc numbers");

    DistributedVector x = vec({2., -3., 3., 4., 5., 5., 9.});
    set.project(x);
    check(x[0] == 1 && x[1] == 1 && std::abs(x[2] - 0.6) < 1e-15 && std::abs(x[3] - 0.8) < 1e-15 &&
            x[4] == 1 && x[5] == 2 && x[6] == 9,
          "projection");
    check(set.is_feasible(x, 1e-15) && set.largest_violation(x) <= 1e-15, "projected is feasible");
    {
      // The set keeps its interval components in a list: bounds set out of order, set twice,
      // and an interval made free again.
      const double     inf = std::numeric_limits<double>::infinity();
      QP::SeparableSet changed(4);
      changed.set_lower_bound(3, 0);
      changed.set_interval(1, 0, 1);
      changed.set_interval(1, -1, 2);
      changed.set_interval(2, 0, 1);
      changed.set_interval(2, -inf, inf);
      DistributedVector y = vec({-5., 3., -7., -1.}), g = vec({1., 1., 1., -1.}), phi, beta;
      changed.project(y);
      check(same_entries(y, vec({-5., 2., -7., 0.})),
            "intervals set out of order, twice, and freed again");
      changed.free_gradient(y, g, phi);
      changed.chopped_gradient(y, g, beta);
      check(same_entries(phi, vec({1., 0., 1., 0.})) && same_entries(beta, vec({0., 1., 0., -1.})),
            "gradient splitting over the changed intervals");
      check(changed.largest_violation(vec({-5., 2.5, -7., -0.5})) == 0.5, "largest violation");
    }

    // x = (0.25, 1 + 1e-15 (active), (1, 0) on the circle, fixed disc, free)
    x                   = vec({0.25, 1 + 1e-15, 1, 0, 1, 2, 0});
    DistributedVector g = vec({1, -1, -2, 3, 1, 1, 5}), phi, beta, gP;
    set.free_gradient(x, g, phi);
    set.chopped_gradient(x, g, beta);
    set.projected_gradient(x, g, gP);
    check(same_entries(phi, vec({1, 0, 0, 0, 0, 0, 5})), "free gradient");
    check(same_entries(beta, vec({0, -1, 0, 3, 0, 0, 0})),
          "chopped gradient: lower end min(g, 0), disc g − min(g·ν, 0)ν, fixed disc 0");
    g = vec({1, 2, 2, 3, 1, 1, 5});
    set.chopped_gradient(x, g, beta);
    check(same_entries(beta, vec({0, 0, 2, 3, 0, 0, 0})), "chopped gradient pointing inwards = g");
    check(gP.l2_norm() == std::sqrt(1 + 25 + 1 + 9.), "projected gradient = φ + β");

    // Rotations: the tangential gradient of an active disc moves into φ; β keeps the inward
    // normal part only.
    using Mode = QP::SeparableSet::DiscMode;
    g          = vec({1, -1, -2, 3, 1, 1, 5});
    set.free_gradient(x, g, phi, Mode::rotations);
    set.chopped_gradient(x, g, beta, Mode::rotations);
    check(same_entries(phi, vec({1, 0, 0, 3, 0, 0, 5})) &&
            same_entries(beta, vec({0, -1, 0, 0, 0, 0, 0})),
          "rotations, disc pressed outwards (σ = 2): tangential part in φ, nothing in β");
    g = vec({1, 2, 2, 3, 1, 1, 5});
    set.free_gradient(x, g, phi, Mode::rotations);
    set.chopped_gradient(x, g, beta, Mode::rotations);
    check(same_entries(phi, vec({1, 0, 0, 3, 0, 0, 5})) &&
            same_entries(beta, vec({0, 0, 2, 0, 0, 0, 0})),
          "rotations, gradient pointing inwards: tangential part in φ, normal part in β");
    {
      g                     = vec({1, -1, -2, 3, 1, 1, 5});
      DistributedVector d   = vec({0, 0, 0.5, 2, 0, 0, 0}), Hd(7);
      DistributedVector tan = d;
      set.remove_normal_parts(x, tan);
      check(same_entries(tan, vec({0, 0, 0, 2, 0, 0, 0})),
            "remove_normal_parts: tangent of the circle");
      set.add_arc_curvature(x, g, d, Hd);
      check(same_entries(Hd, vec({0, 0, 0, 4, 0, 0, 0})) && set.arc_curvature(x, g, d) == 8 &&
              d * Hd == set.arc_curvature(x, g, d),
            "arc curvature σ/r ‖t‖² = 2 · 4 and its operator");
      check(set.moves_active_discs(x, d) && !set.moves_active_discs(x, vec({1, 0, 0, 0, 0, 0, 1})),
            "moves_active_discs");
      check(set.max_feasible_step(x, tan, Mode::rotations) ==
                std::numeric_limits<double>::infinity() &&
              set.max_feasible_step(x, tan) == 0,
            "rotations: an active disc does not limit a step along its circle");
    }

    DistributedVector y = vec({0., 1e-300, 0, 0, 1, 2, 0});
    QP::SeparableSet  lower(7);
    lower.set_lower_bound(1, 0);
    lower.free_gradient(y, g, phi);
    check(phi[1] == g[1], "x_i = 1e-300 above the bound 0 is not active");
    DistributedVector z = vec({0, 0, 1 - 1e-13, 0, 1, 2, 0});
    set.free_gradient(z, g, phi);
    check(phi[2] == 0 && phi[3] == 0, "‖x − c‖ = r(1 − 1e-13) is on the disc boundary");

    // Feasible steps.
    DistributedVector p(7);
    x    = vec({0.25, 2, 0, 0, 1, 2, 0});
    p[0] = -0.5;
    check(set.max_feasible_step(x, p) == 1.5, "interval ratio test (upper end)");
    p[0] = 0.25;
    check(set.max_feasible_step(x, p) == 1, "interval ratio test (lower end)");
    p    = 0;
    p[1] = 4;
    check(set.max_feasible_step(x, p) == 0.25, "lower bound ratio test");
    p    = 0;
    p[2] = -1;
    check(std::abs(set.max_feasible_step(x, p) - 1) < 1e-15, "disc from its centre");
    x[2] = 1;
    p[2] = 1;
    check(std::abs(set.max_feasible_step(x, p) - 2) < 1e-15, "disc from the boundary inwards");
    p[2] = -1;
    check(set.max_feasible_step(x, p) == 0, "disc from the boundary outwards: 0");
    p[2] = 0;
    p[3] = 1;
    check(set.max_feasible_step(x, p) == 0, "tangent at the boundary: 0");
    p    = 0;
    p[4] = 1e-3;
    check(set.max_feasible_step(x, p) == 0, "fixed disc: 0");
    p    = 0;
    p[6] = 1;
    check(set.max_feasible_step(x, p) == infinity, "free component: +∞");
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  check_set();

  using R = Role;
  // Every variant; returns the default's result.
  const auto both = [](const std::string &name, const Problem &p, const DistributedVector &x0) {
    const Result r = solve_and_check(name, p, x0);
    solve_and_check(name, p, x0, 1, Variant::fixed_discs);
    solve_and_check(name, p, x0, 1, Variant::fixed_step);
    solve_and_check(name, p, x0, 1, Variant::projected_cg);
    solve_and_check(name, p, x0, 1, Variant::preconditioned);
    solve_and_check(name, p, x0, 1, Variant::recursive_arcs);
    solve_and_check(name, p, x0, 1, Variant::mean_diagonal_arcs);
    return r;
  };
  // The problem with A and b scaled against the unscaled one, all solved to ‖g^P‖ ≤ 1e-10‖b‖.
  // By 2^∓37 (about 7e-12 and 1.4e11) floating-point arithmetic scales exactly, so any absolute
  // threshold would show as a different path: the same counts and bit for bit the same x. By
  // 1e-11 and 1e11 the rounding differs and steps decided on gradients near the tolerance may
  // differ: the same x to 1e-9.
  const auto scaled = [](const std::string &name, const Problem &p, const Variant variant) {
    const DistributedVector x0(p.n);
    const Result            reference = solve_and_check(name, p, x0, 1, variant, 1e-10);
    for (const double s : {std::ldexp(1., -37), std::ldexp(1., 37), 1e-11, 1e11})
      {
        const bool        exact = s == std::ldexp(1., -37) || s == std::ldexp(1., 37);
        const Result      r     = solve_and_check(name + ", scaled", p, x0, s, variant, 1e-10);
        DistributedVector d(r.x);
        d -= reference.x;
        check(d.l2_norm() <= (exact ? 0. : 1e-9) * reference.x.l2_norm(),
              std::string(exact ? "bit for bit " : "") +
                "the same x as unscaled: " + sci(d.l2_norm() / reference.x.l2_norm()));
        if (exact)
          check(r.report.iterations == reference.report.iterations &&
                  r.report.hessian_multiplications == reference.report.hessian_multiplications,
                "same counts as unscaled (" + std::to_string(r.report.iterations) + " steps, " +
                  std::to_string(r.report.hessian_multiplications) + " multiplications)");
      }
  };

  // Generic mix: every kind of block.
  const Problem           mix = make_problem({{R::free, 6},
                                              {R::interval_inside, 3},
                                              {R::interval_lower, 3},
                                              {R::interval_upper, 3},
                                              {R::interval_fixed, 1},
                                              {R::lower_inside, 3},
                                              {R::lower_active, 4},
                                              {R::upper_active, 2},
                                              {R::disc_inside, 2},
                                              {R::disc_centre, 1},
                                              {R::disc_active, 4},
                                              {R::disc_fixed, 1}});
  const DistributedVector zero_mix(mix.n);
  both("generic mix", mix, zero_mix);
  scaled("generic mix", mix, Variant::rotations);
  scaled("generic mix", mix, Variant::fixed_discs);
  scaled("generic mix", mix, Variant::fixed_step);
  scaled("generic mix", mix, Variant::projected_cg);
  scaled("generic mix", mix, Variant::recursive_arcs);
  scaled("generic mix", mix, Variant::mean_diagonal_arcs);
  {
    DistributedVector x0(mix.n);
    for (auto &v : x0)
      v = 20 * uniform(random_engine);
    check(mix.set.largest_violation(x0) > 1, "start outside Ω");
    both("generic mix from outside Ω", mix, x0);
  }
  {
    const Problem p = make_problem({{R::free, 10}, {R::disc_centre, 8}, {R::lower_inside, 6}});
    both("solution at disc centres", p, DistributedVector(p.n));
  }
  {
    const Problem p = make_problem(
      {{R::free, 10}, {R::disc_degenerate, 8}, {R::disc_active, 4}, {R::lower_active, 4}});
    both("disc boundary with zero gradient (σ = 0)", p, DistributedVector(p.n));
  }
  {
    const Problem p = make_problem({{R::interval_lower, 6},
                                    {R::interval_upper, 6},
                                    {R::lower_active, 6},
                                    {R::upper_active, 4},
                                    {R::disc_active, 10},
                                    {R::disc_fixed, 2}});
    both("all constraints active", p, DistributedVector(p.n));
  }
  {
    const Problem p = make_problem({{R::free, 10},
                                    {R::interval_inside, 6},
                                    {R::lower_inside, 6},
                                    {R::disc_inside, 8},
                                    {R::disc_centre, 2}});
    // The unconstrained minimizer A⁻¹b, independently of x*.
    FullMatrix<double> A_inverse(p.n, p.n);
    A_inverse.invert(p.A);
    DistributedVector x_free(p.n);
    multiply(A_inverse, p.b, x_free);
    const Result      r = solve_and_check("no constraint active", p, DistributedVector(p.n));
    DistributedVector d(r.x);
    d -= x_free;
    check(d.l2_norm() <= 1e-8 * x_free.l2_norm(),
          "= unconstrained solution A⁻¹b: " + sci(d.l2_norm() / x_free.l2_norm()));
  }
  {
    // Strong curvature: σ/r up to 1.5e4 > ‖A‖ = 1e3. The model step handles it; the fixed step
    // ᾱ increases f, is replaced by P(x − ᾱg) (the fallback path) and crawls: it is only run
    // for 2000 steps and must decrease f and stay feasible.
    const Problem p = make_problem({{R::free, 10}, {R::disc_curved, 8}, {R::lower_active, 4}});
    solve_and_check("strongly curved discs (r ≤ 1e-3)", p, DistributedVector(p.n));
    std::cout << "strongly curved discs, fixed-step proportioning, 2000 steps" << std::endl;
    QP::MPGP<DistributedVector>::AdditionalData options;
    options.tolerance                 = 1e-12 * QP::l2_norm(p.b);
    options.disc_rotations            = false;
    options.proportioning_line_search = false;
    options.max_iterations            = 2000;
    double     f_last = std::numeric_limits<double>::infinity(), increase = 0;
    const auto A = [&](const DistributedVector &v, DistributedVector &w) { multiply(p.A, v, w); };
    DistributedVector x(p.n), Ax(p.n);
    const auto        f = [&]() {
      multiply(p.A, x, Ax);
      return 0.5 * (x * Ax) - p.b * x;
    };
    options.monitor = [&](unsigned int, double) {
      const double fx = f();
      increase        = std::max(increase, fx - f_last);
      f_last          = fx;
    };
    const auto r = QP::MPGP<DistributedVector>(options).solve(A, p.b, p.set, x);
    check(r.proportioning_fallbacks > 0 && increase <= 1e-12 * std::abs(f_last),
          "f decreases with " + std::to_string(r.proportioning_fallbacks) + " fallbacks in " +
            std::to_string(r.proportioning_steps) + " proportioning steps; ‖g^P‖/‖b‖ = " +
            sci(r.relative_residual) + (r.converged ? " (converged)" : " (not converged)"));
    check(violation(p, x) <= 1e-14 * x.linfty_norm(), "feasible");
  }
  {
    const Problem p =
      make_problem({{R::free, 8}, {R::disc_fixed, 8}, {R::disc_active, 4}, {R::interval_fixed, 4}});
    both("zero-radius discs (fixed blocks)", p, DistributedVector(p.n));
  }
  {
    const Problem p = make_problem({{R::free, 8},
                                    {R::interval_inside, 6},
                                    {R::interval_lower, 6},
                                    {R::interval_upper, 6},
                                    {R::lower_inside, 8},
                                    {R::lower_active, 10},
                                    {R::upper_active, 4}});
    const Result  r = solve_and_check("bounds only (MPRGP)", p, DistributedVector(p.n));
    check(r.report.proportioning_fallbacks == 0, "no projected proportioning without discs");
    scaled("bounds only (MPRGP)", p, Variant::rotations);
    scaled("bounds only (MPRGP)", p, Variant::projected_cg);
  }
  {
    // Many constraints that become active from a start where all are free: the fixed-step
    // expansion activates about one per expansion, the projected CG step all those it crosses.
    const Problem p = make_problem({{R::free, 20}, {R::lower_inside, 40}, {R::lower_active, 200}});
    const Result  fixed = solve_and_check("many active bounds", p, DistributedVector(p.n));
    const Result  pcg =
      solve_and_check("many active bounds", p, DistributedVector(p.n), 1, Variant::projected_cg);
    check(2 * pcg.report.expansion_steps < fixed.report.expansion_steps &&
            pcg.report.hessian_multiplications < fixed.report.hessian_multiplications,
          "projected CG expansion: " + std::to_string(pcg.report.expansion_steps) +
            " expansions, " + std::to_string(pcg.report.hessian_multiplications) +
            " multiplications against " + std::to_string(fixed.report.expansion_steps) + ", " +
            std::to_string(fixed.report.hessian_multiplications) + " with the fixed step");
  }
  {
    // Preconditioning in face: A = S A₀ S with S = diag(10^(2i/n)) (condition number about 1e7)
    // and the same KKT point; M = diag(A)⁻¹ removes the scaling, so MPGP needs fewer
    // multiplications with it than without.
    Problem            p = make_problem({{R::free, 20},
                                         {R::lower_inside, 10},
                                         {R::lower_active, 10},
                                         {R::disc_inside, 4},
                                         {R::disc_active, 6}});
    const unsigned int n = p.n;
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        p.A(i, j) *= std::pow(10., 2. * i / n) * std::pow(10., 2. * j / n);
    multiply(p.A, p.x_star, p.b);
    p.b -= p.g_star;
    p.A_norm *= 1e4; // ‖S A₀ S‖ ≤ ‖S‖² ‖A₀‖
    const Result plain = solve_and_check("badly scaled", p, DistributedVector(n));
    const Result pre =
      solve_and_check("badly scaled", p, DistributedVector(n), 1, Variant::preconditioned);
    check(2 * pre.report.hessian_multiplications < plain.report.hessian_multiplications &&
            pre.report.preconditioner_applications > 0,
          "preconditioned in face: " + std::to_string(pre.report.hessian_multiplications) +
            " multiplications against " + std::to_string(plain.report.hessian_multiplications) +
            " (" + std::to_string(pre.report.preconditioner_applications) + " applications of M)");
  }
  {
    // Most blocks on their circles, as the slipping nodes of a contact zone with friction: the
    // recursive update saves the second multiplication of most steps along the circles.
    const Problem p = make_problem(
      {{R::free, 10}, {R::disc_active, 30}, {R::disc_inside, 4}, {R::lower_active, 4}});
    const Result exact = solve_and_check("mostly active discs", p, DistributedVector(p.n));
    const Result recursive =
      solve_and_check("mostly active discs", p, DistributedVector(p.n), 1, Variant::recursive_arcs);
    check(recursive.report.recursive_gradient_updates > 0 &&
            recursive.report.hessian_multiplications < exact.report.hessian_multiplications,
          "recursive gradient along the circles: " +
            std::to_string(recursive.report.hessian_multiplications) + " multiplications (" +
            std::to_string(recursive.report.recursive_gradient_updates) +
            " recursive updates) against " + std::to_string(exact.report.hessian_multiplications));
  }
  {
    // Hutchinson's estimate of tr(A)/n: exact for a diagonal matrix (vᵢ² = 1), and within a few
    // percent of it for a dense one with many probes (its spread falls like 1/√probes).
    const unsigned int n = 40;
    DistributedVector  d(n);
    for (auto &di : d)
      di = random_in(0.1, 10);
    const double exact_d    = d.mean_value();
    const double estimate_d = QP::estimate_mean_diagonal<DistributedVector>(
      [&](const DistributedVector &v, DistributedVector &w) { w = v, w.scale(d); }, d, 3);
    check(std::abs(estimate_d - exact_d) <= 1e-14 * exact_d,
          "mean diagonal of a diagonal matrix: " + sci(estimate_d) + " against " + sci(exact_d));
    const FullMatrix<double> A     = random_spd(n, 1e3);
    double                   trace = 0;
    for (unsigned int i = 0; i < n; ++i)
      trace += A(i, i);
    const double estimate = QP::estimate_mean_diagonal<DistributedVector>(
      [&](const DistributedVector &v, DistributedVector &w) { multiply(A, v, w); }, d, 4000);
    check(std::abs(estimate - trace / n) <= 0.05 * trace / n,
          "mean diagonal of a dense matrix, 4000 probes: " + sci(estimate) + " against " +
            sci(trace / n));
  }
  std::cout << (n_failures == 0 ? "PASSED" : "FAILED") << std::endl;
  return n_failures;
}
