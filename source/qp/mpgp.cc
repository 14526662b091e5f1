#include <deal.II/base/exceptions.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/base/reproducible_partitioner.h>
#include <feticontact/qp/mpgp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace FetiContact::QP
{
  using namespace dealii;

  namespace
  {
    /**
     * Entries of the sequence of std::minstd_rand(seed), looked up by position: the j-th output
     * (j = 0, 1, …) is seed · 48271^(j+1) mod (2³¹ − 1). A vector's entry with global index i
     * takes output number offset + i, so a start vector is the same on any number of ranks and
     * in any order of the local entries; successive indices cost one multiplication, others a
     * modular power.
     */
    class MinstdSequence
    {
    public:
      explicit MinstdSequence(const std::uint64_t seed)
        : seed(seed % modulus == 0 ? 1 : seed % modulus)
      {}

      /** Output number @p j. */
      std::uint64_t
      operator()(const std::uint64_t j)
      {
        if (j != last_index + 1 || !started)
          {
            std::uint64_t power = 1, base = multiplier;
            for (std::uint64_t e = j + 1; e > 0; e >>= 1, base = base * base % modulus)
              if (e & 1)
                power = power * base % modulus;
            last_value = seed * power % modulus;
          }
        else
          last_value = last_value * multiplier % modulus;
        last_index = j;
        started    = true;
        return last_value;
      }

      static constexpr std::uint64_t modulus = 2147483647, multiplier = 48271;

    private:
      std::uint64_t seed, last_index = 0, last_value = 0;
      bool          started = false;
    };
  } // namespace

  template <typename VectorType>
  double
  estimate_norm(const Operator<VectorType> &A,
                const VectorType           &model,
                const unsigned int          iterations)
  {
    if (model.size() == 0)
      return 0;
    VectorType v, Av;
    v.reinit(model, true);
    Av.reinit(model);
    MinstdSequence random(20120101);
    for (unsigned int i = 0; i < v.locally_owned_size(); ++i)
      v.local_element(i) = double(random(Reductions<VectorType>::global_index(v, i))) /
                             double(MinstdSequence::modulus - 1) -
                           0.5;
    const double v_norm = l2_norm(v);
    for (double &v_i : v)
      v_i /= v_norm;
    double estimate = 0;
    for (unsigned int k = 0; k < std::max(iterations, 1u); ++k)
      {
        A(v, Av);
        estimate = l2_norm(Av);
        if (!(estimate > 0) || !std::isfinite(estimate))
          return estimate > 0 ? estimate : 0.;
        v.equ(1. / estimate, Av);
      }
    return estimate;
  }

  template <typename VectorType>
  double
  estimate_mean_diagonal(const Operator<VectorType> &A,
                         const VectorType           &model,
                         const unsigned int          probes)
  {
    const unsigned int n = model.size();
    if (n == 0)
      return 0;
    VectorType v, Av;
    v.reinit(model, true);
    Av.reinit(model);
    double         sum = 0;
    MinstdSequence random(20260101);
    for (unsigned int k = 0; k < std::max(probes, 1u); ++k)
      {
        for (unsigned int i = 0; i < v.locally_owned_size(); ++i)
          v.local_element(i) =
            random(std::uint64_t(k) * n + Reductions<VectorType>::global_index(v, i)) % 2 == 0 ?
              1. :
              -1.;
        A(v, Av);
        sum += dot(v, Av);
      }
    return sum / (double(std::max(probes, 1u)) * n);
  }

  void
  MPGPParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Maximum iterations",
                      "10000",
                      Patterns::Integer(1),
                      "The limit of MPGP's steps per solve (per inner solve of SMALBE).");
    prm.declare_entry("Disc rotations",
                      "true",
                      Patterns::Bool(),
                      "Conjugate gradient steps also move active discs along their circles "
                      "(true), or only proportioning steps do, as in Dostál–Kozubek and Kučera's "
                      "KPG (false; much slower when most nodes slip).");
    prm.declare_entry("Expansion step",
                      "auto",
                      Patterns::Selection("auto|fixed|projected cg"),
                      "How a conjugate gradient step that leaves the feasible set activates "
                      "constraints: 'fixed' (Dostál–Schöberl: the feasible half step, then the "
                      "projected step of fixed length ᾱ = 1.9/‖A‖, which activates about one "
                      "constraint per expansion) or 'projected cg' (the whole conjugate gradient "
                      "step projected onto the feasible set, kept if the energy decreased, else "
                      "the fixed step; Kružík et al. 2020). 'auto': projected cg for the mpgp "
                      "algorithm, fixed otherwise.");
    prm.declare_entry("Recursive gradient tolerance",
                      "auto",
                      Patterns::Anything(),
                      "A number η ≥ 0 or 'auto' (0.1 for the mpgp algorithm, 0 otherwise). After "
                      "a step that the projection onto the feasible set moved off its line "
                      "(conjugate gradient steps along the circles of slipping nodes, projected "
                      "CG expansions), the gradient is updated as g − αAp, leaving out A times the "
                      "return onto the feasible set, as long as the bound of the error, (2/ᾱ) × "
                      "the summed returns, stays below η‖g^P‖; every stopping decision is made on "
                      "a recomputed gradient. 0: recompute after every such step.");
    prm.declare_entry("Arc preconditioner scale",
                      "auto",
                      Patterns::Selection("auto|norm|mean diagonal"),
                      "With Disc rotations: the conjugate gradient steps along the circles of "
                      "slipping nodes are preconditioned by 1/(1 + σ/(r a)) (σ the force pressing "
                      "a node's tangential multiplier outwards, r the slip bound), a the scale of "
                      "the Hessian A: 'norm' its norm bound, 'mean diagonal' tr(A)/m, estimated "
                      "once from 10 multiplications (Hutchinson), the Jacobi scaling along the "
                      "circles. 'auto': mean diagonal for the mpgp algorithm, norm otherwise.");
  }

  void
  MPGPParameters::parse_parameters(ParameterHandler &prm)
  {
    max_iterations                   = prm.get_integer("Maximum iterations");
    disc_rotations                   = prm.get_bool("Disc rotations");
    const std::string expansion_text = prm.get("Expansion step");
    if (expansion_text != "auto")
      expansion =
        expansion_text == "projected cg" ? Expansion::projected_cg : Expansion::fixed_step;
    const std::string eta_text = InputParsing::trim(prm.get("Recursive gradient tolerance"));
    if (eta_text != "auto")
      {
        const std::string what       = "Contact solver/MPGP/Recursive gradient tolerance";
        recursive_gradient_tolerance = InputParsing::parse_double(eta_text, what);
        require(recursive_gradient_tolerance >= 0,
                what + " must be 'auto' or a number of at least 0; got '" + eta_text + "'.");
      }
    const std::string scale_text = prm.get("Arc preconditioner scale");
    if (scale_text != "auto")
      arc_scale_estimate =
        scale_text == "mean diagonal" ? ArcScale::mean_diagonal : ArcScale::norm_bound;
  }

  template <typename VectorType>
  MPGP<VectorType>::MPGP()
    : additional_data()
  {}

  template <typename VectorType>
  MPGP<VectorType>::MPGP(const AdditionalData &data)
    : additional_data(data)
  {}

  template <typename VectorType>
  typename MPGP<VectorType>::AdditionalData &
  MPGP<VectorType>::data()
  {
    return additional_data;
  }

  template <typename VectorType>
  void
  MPGP<VectorType>::multiply(const VectorType &v, VectorType &w)
  {
    (*A)(v, w);
    ++statistics.hessian_multiplications;
  }

  template <typename VectorType>
  void
  MPGP<VectorType>::recompute_gradient()
  {
    multiply(*x, g);
    g -= *b;
    gradient_error = 0;
  }

  template <typename VectorType>
  bool
  MPGP<VectorType>::choose_step()
  {
    alpha_bar = additional_data.step;
    if (!(alpha_bar > 0))
      {
        const unsigned int iterations = std::max(additional_data.norm_iterations, 1u);
        const double       norm       = estimate_norm(*A, *b, iterations);
        statistics.hessian_multiplications += iterations;
        statistics.norm_estimate_multiplications = iterations;
        if (!(norm > 0) || !std::isfinite(norm))
          return false;
        alpha_bar = 1.9 / (1.05 * norm);
      }
    statistics.step = alpha_bar;
    return true;
  }

  template <typename VectorType>
  void
  MPGP<VectorType>::update_sets()
  {
    // z = M⁻¹φ, the search direction before conjugation: φ itself, or with rotations φ
    // divided on the tangents of pressed discs by 1 + (σ_k/r_k)/a with a = AdditionalData::
    // arc_scale or ‖A‖ (the curvature of a small, strongly pressed circle dominates the Hessian
    // along it; SeparableSet::precondition_arcs). With a preconditioner in face:
    // z = D^(−½) R_F M R_F D^(−½) φ (D the arc factor, R_F the restriction to the face, which φ
    // already satisfies).
    set->free_gradient(*x, g, phi, mode);
    set->chopped_gradient(*x, g, beta, mode);
    norm_gP = std::sqrt(norm_sqr(phi) + norm_sqr(beta)); // φ·β = 0
    z       = phi;
    if (precondition)
      set->precondition_arcs(*x, g, arc_scale, z, in_face ? 0.5 : 1.);
    if (in_face)
      {
        additional_data.preconditioner(z, Mz);
        ++statistics.preconditioner_applications;
        set->free_gradient(*x, Mz, z, mode);
        if (precondition)
          set->precondition_arcs(*x, g, arc_scale, z, 0.5);
      }
  }

  template <typename VectorType>
  bool
  MPGP<VectorType>::increased() const
  {
    // f(x) − f(x_old) = ½(x − x_old)ᵀ(g + g_old) (exact for a quadratic), and whether it is an
    // increase beyond the rounding level (the projection onto a disc is exact only to ε r, times
    // the multiplier g·ν).
    const VectorType &xx    = *x;
    const double      df    = Reductions<VectorType>::sum(xx, [&](const unsigned int i) {
      return (xx.local_element(i) - x_old.local_element(i)) *
             (g.local_element(i) + g_old.local_element(i));
    });
    const double      noise = Reductions<VectorType>::sum(xx, [&](const unsigned int i) {
      return std::abs(xx.local_element(i)) *
             (std::abs(g.local_element(i)) + std::abs(g_old.local_element(i)));
    });
    return df > 32 * std::numeric_limits<double>::epsilon() * noise;
  }

  template <typename VectorType>
  bool
  MPGP<VectorType>::gradient_after_projection(const double alpha)
  {
    // With AdditionalData::recursive_gradient_tolerance > 0: g ← g − αAp, leaving out A d for
    // the return d = x − (x_old − α p) onto Ω, if the error bound (2/ᾱ ≥ ‖A‖) summed since the
    // last recomputation stays below η‖g^P‖ and the energy test on the updated g sees no
    // increase; otherwise g ← Ax − b. gradient_error bounds ‖g − (Ax − b)‖.
    if (additional_data.recursive_gradient_tolerance > 0)
      {
        y = *x;
        y -= x_old;
        y.add(alpha, p);
        const double drift = 2. / alpha_bar * l2_norm(y);
        if (gradient_error + drift <= additional_data.recursive_gradient_tolerance * norm_gP)
          {
            g.add(-alpha, Ap);
            gradient_error += drift;
            if (!increased())
              {
                ++statistics.recursive_gradient_updates;
                return true;
              }
          }
      }
    recompute_gradient();
    return false;
  }

  template <typename VectorType>
  void
  MPGP<VectorType>::projected_gradient_step()
  {
    *x = x_old;
    x->add(-alpha_bar, g_old);
    set->project(*x);
    recompute_gradient();
    ++statistics.proportioning_fallbacks;
  }

  template <typename VectorType>
  void
  MPGP<VectorType>::start(VectorType *gradient)
  {
    // The caller's gradient Ax₀ − b stands for the first multiplication if x₀ ∈ Ω already: if
    // the projection moves x₀ by no more than the rounding of a projection onto a circle
    // (x₀ returned by an earlier solve), the known gradient is off by at most ‖A‖ times that.
    const bool known_gradient = gradient && gradient->size() == b->size();
    if (known_gradient)
      x_old = *x;
    set->project(*x);
    bool moved = true;
    if (known_gradient)
      {
        y = *x;
        y -= x_old;
        moved = linfty_norm(y) > 4 * std::numeric_limits<double>::epsilon() * linfty_norm(*x);
      }
    if (!moved)
      g = *gradient;
    else
      recompute_gradient();
    update_sets();
    p        = z;
    p_is_phi = true;
  }

  template <typename VectorType>
  bool
  MPGP<VectorType>::stop() const
  {
    return norm_gP <= additional_data.tolerance ||
           (additional_data.stop_when && additional_data.stop_when(*x, norm_gP));
  }

  template <typename VectorType>
  bool
  MPGP<VectorType>::done()
  {
    if (!stop())
      return false;
    if (gradient_error == 0)
      return true;
    recompute_gradient();
    update_sets();
    return stop();
  }

  template <typename VectorType>
  bool
  MPGP<VectorType>::proportional()
  {
    y = *x;
    y.add(-alpha_bar, phi);
    set->project(y);
    const VectorType &xx = *x;
    const double      phi_tilde_phi =
      Reductions<VectorType>::sum(xx,
                                  [&](const unsigned int i) {
                                    return (xx.local_element(i) - y.local_element(i)) *
                                           phi.local_element(i);
                                  }) /
      alpha_bar;
    return norm_sqr(beta) <= additional_data.gamma * additional_data.gamma * phi_tilde_phi;
  }

  template <typename VectorType>
  typename MPGP<VectorType>::Outcome
  MPGP<VectorType>::step_along_p()
  {
    // gᵀp = φᵀp: p lives where φ does (free blocks, tangents of active discs). φᵀp avoids the
    // cancellation of the large normal parts of g on pressed discs, which makes gᵀp
    // meaningless (even negative) once φ is near the rounding level of g.
    double gp = dot(phi, p);
    if (!(gp > 0) && !p_is_phi)
      {
        p        = z;
        p_is_phi = true;
        gp       = dot(phi, p);
      }
    multiply(p, Ap);
    // Along the circles of active discs the second derivative of f gains the curvature term
    // (SeparableSet::arc_curvature); without rotations it is zero.
    const bool   arc = mode == SeparableSet::DiscMode::rotations && set->moves_active_discs(*x, p);
    const double curvature = dot(p, Ap) + (arc ? set->arc_curvature(*x, g, p) : 0.);
    if (!(curvature > 0) || !(gp > 0))
      {
        // A not positive definite on φ, or φ = 0 at the rounding level: a breakdown; a
        // conjugated direction is replaced by z first.
        if (p_is_phi)
          return Outcome::breakdown;
        p        = z;
        p_is_phi = true;
        return Outcome::retry;
      }
    const double alpha_cg = gp / curvature;
    const double alpha_f  = set->max_feasible_step(*x, p, mode);
    if (alpha_cg <= alpha_f)
      conjugate_gradient_step(alpha_cg, curvature, arc);
    else
      expansion_step(alpha_cg, alpha_f);
    return Outcome::step;
  }

  template <typename VectorType>
  void
  MPGP<VectorType>::conjugate_gradient_step(const double alpha_cg,
                                            const double curvature,
                                            const bool   arc)
  {
    if (arc)
      {
        x_old   = *x;
        g_old   = g;
        phi_old = phi;
      }
    x->add(-alpha_cg, p);
    set->project(*x);
    // With rotations the projection back onto the circles moved x off the line: recompute g,
    // and fall back to the projected gradient step if f increased.
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
        return;
      }
    double gamma_cg = dot(z, Ap) / curvature;
    if (arc)
      {
        // Hestenes–Stiefel with the change of the tangential gradient along the step, both
        // transported to the tangent spaces at the new x: it carries the curvature of the
        // circles as it is along the step, not only at its start.
        Hp = phi_old;
        Hp -= phi;
        set->remove_normal_parts(*x, Hp);
        set->remove_normal_parts(*x, p);
        const double pHp = dot(p, Hp);
        gamma_cg         = pHp > 0 ? dot(z, Hp) / pHp : 0.;
      }
    p.sadd(-gamma_cg, 1., z); // p ← z − γ p
    set->remove_normal_parts(*x, p);
    p_is_phi = false;
    ++statistics.cg_steps;
  }

  template <typename VectorType>
  void
  MPGP<VectorType>::expansion_step(const double alpha_cg, const double alpha_f)
  {
    bool expanded = false;
    if (additional_data.expansion == AdditionalData::Expansion::projected_cg)
      {
        // The whole conjugate gradient step, projected: every constraint that it crosses
        // becomes active at once. Kept only if f decreased.
        x_old                     = *x;
        g_old                     = g;
        const double error_before = gradient_error;
        x->add(-alpha_cg, p);
        set->project(*x);
        expanded = gradient_after_projection(alpha_cg) || !increased();
        if (!expanded)
          {
            *x             = x_old;
            g              = g_old;
            gradient_error = error_before;
            ++statistics.expansion_fallbacks;
          }
      }
    if (!expanded)
      {
        // Feasible half step, then the fixed-step projected step along the free gradient of the
        // fixed-disc mode (its decrease of f is guaranteed for ᾱ ≤ 2/‖A‖; a rotation of a
        // strongly pressed disc by ᾱ would not be).
        x->add(-alpha_f, p);
        set->project(*x);
        g.add(-alpha_f, Ap);
        set->free_gradient(*x, g, phi, SeparableSet::DiscMode::fixed);
        x->add(-alpha_bar, phi);
        set->project(*x);
        recompute_gradient();
      }
    update_sets();
    p        = z;
    p_is_phi = true;
    ++statistics.expansion_steps;
  }

  template <typename VectorType>
  typename MPGP<VectorType>::Outcome
  MPGP<VectorType>::proportioning_step()
  {
    if (mode == SeparableSet::DiscMode::rotations || !set->nonzero_on_discs(beta))
      {
        // β points into Ω along a line (on discs, with rotations, along the inward normal):
        // exact line search, cut at the far end of the feasible segment.
        multiply(beta, Ap);
        const double dAd = dot(beta, Ap);
        if (!(dAd > 0))
          return Outcome::breakdown;
        const double alpha = std::min(norm_sqr(beta) / dAd, set->max_feasible_step(*x, beta));
        x->add(-alpha, beta);
        set->project(*x);
        g.add(-alpha, Ap);
      }
    else
      {
        x_old        = *x;
        g_old        = g;
        double alpha = alpha_bar;
        if (additional_data.proportioning_line_search)
          {
            // Minimizer of the second-order model of f along the arc P_Ω(x − αβ).
            multiply(beta, Ap);
            const double curvature = dot(beta, Ap) + set->arc_curvature(*x, g, beta);
            if (!(curvature > 0))
              return Outcome::breakdown;
            alpha = norm_sqr(beta) / curvature;
          }
        x->add(-alpha, beta);
        set->project(*x);
        recompute_gradient();
        if (increased())
          projected_gradient_step();
      }
    update_sets();
    p        = z;
    p_is_phi = true;
    ++statistics.proportioning_steps;
    return Outcome::step;
  }

  template <typename VectorType>
  typename MPGP<VectorType>::Statistics
  MPGP<VectorType>::solve(const Operator<VectorType> &A_in,
                          const VectorType           &b_in,
                          const SeparableSet         &set_in,
                          VectorType                 &x_in,
                          VectorType                 *gradient)
  {
    const unsigned int n = b_in.size();
    AssertThrow(set_in.size() == b_in.locally_owned_size() && x_in.size() == n,
                ExcMessage("MPGP: sizes of b (" + std::to_string(n) + "), x (" +
                           std::to_string(x_in.size()) + ") and the set (" +
                           std::to_string(set_in.size()) + ") differ."));
    AssertThrow(additional_data.gamma > 0, ExcMessage("MPGP: Γ must be positive."));
    A          = &A_in;
    b          = &b_in;
    set        = &set_in;
    x          = &x_in;
    statistics = Statistics();
    if (!choose_step())
      {
        // A vanishes on the start vector (or n = 0): nothing sensible to iterate with.
        statistics.converged = (n == 0);
        if (gradient)
          *gradient = VectorType();
        return statistics;
      }
    mode = additional_data.disc_rotations ? SeparableSet::DiscMode::rotations :
                                            SeparableSet::DiscMode::fixed;
    precondition =
      mode == SeparableSet::DiscMode::rotations && additional_data.precondition_rotations;
    arc_scale      = additional_data.arc_scale > 0 ? additional_data.arc_scale : 1.9 / alpha_bar;
    in_face        = static_cast<bool>(additional_data.preconditioner);
    gradient_error = 0;
    for (auto *v : {&g, &p, &Ap, &Hp, &phi, &beta, &y, &z})
      v->reinit(b_in);
    if (in_face)
      Mz.reinit(b_in);

    start(gradient);
    bool converged = done();
    while (!converged && std::isfinite(norm_gP) &&
           statistics.iterations < additional_data.max_iterations)
      {
        const Outcome outcome = proportional() ? step_along_p() : proportioning_step();
        if (outcome == Outcome::breakdown)
          break;
        if (outcome == Outcome::retry)
          continue;
        ++statistics.iterations;
        if (additional_data.monitor)
          additional_data.monitor(statistics.iterations, norm_gP);
        converged = done();
      }

    if (gradient_error > 0)
      {
        // Stopped without convergence (steps exhausted, breakdown): report the exact ‖g^P‖.
        recompute_gradient();
        update_sets();
      }
    if (gradient)
      *gradient = g;
    statistics.projected_gradient_norm = norm_gP;
    statistics.relative_residual       = l2_norm(b_in) > 0 ? norm_gP / l2_norm(b_in) : norm_gP;
    statistics.converged               = converged;
    return statistics;
  }
  template class MPGP<DistributedVector>;
  template double
  estimate_norm(const Operator<DistributedVector> &, const DistributedVector &, const unsigned int);
  template double
  estimate_mean_diagonal(const Operator<DistributedVector> &,
                         const DistributedVector &,
                         const unsigned int);
} // namespace FetiContact::QP
