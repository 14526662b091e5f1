#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/qp/vector_reductions.h>

#include <array>
#include <vector>

namespace FetiContact::QP
{
  /**
   * A closed convex set Ω = Ω_1 × … × Ω_s over the n components of a vector, each block one of
   *  - a free component (Ω_i = R; the default for every component),
   *  - an interval l ≤ x_i ≤ u on one component (either end may be ±∞; a lower bound x_i ≥ l is
   *    the interval [l, +∞); l = u fixes the component),
   *  - a disc on two components (i, j): ‖(x_i, x_j) − c‖ ≤ r with centre c ∈ R² and radius
   *    r ≥ 0 (r = 0 fixes the block at c; r = +∞ leaves it free, never active).
   * In FETI contact: λ_N ≥ 0 (lower bounds), ‖(λ_t1, λ_t2)_k‖ ≤ g_k (discs centred at 0),
   * λ_E free (doc/formulation.md, "The dual problem").
   *
   * The set supplies what MPRGP/MPGP need (doc/formulation.md, "Algorithms"): the Euclidean
   * projection P_Ω, the free gradient φ, the chopped gradient β, the projected gradient g^P = φ + β
   * and the feasible step length. "Active" (on the boundary) is decided robustly: an interval end
   * is active when x_i equals it or lies within 1e-14 times the interval's scale max(|l|, |u|)
   * (finite ends only) of it; a disc is active when ‖x − c‖ ≥ r(1 − 1e-12); fixed blocks (l = u, r
   * = 0) are always active, and so is an interval narrower than twice the interval tolerance. φ and
   * β have disjoint supports (inactive blocks and active blocks).
   *
   * The operations are templates on the vector type, instantiated for DistributedVector (deal.II's
   * distributed vector). Every rank holds the set of its owned entries: the component indices
   * are local (the two of a disc on one rank), size() is the local size,
   * and the scalar results (max_feasible_step(), arc_curvature(), support(), …) are reduced over
   * the ranks (Reductions), so every rank gets the same number. Those are collective.
   */
  class SeparableSet
  {
  public:
    /** The set R^n: every component free (n local components, see the class documentation). */
    explicit SeparableSet(const unsigned int n);

    /** n, the number of components. */
    unsigned int
    size() const;

    /** Makes component i the interval block lower ≤ x_i ≤ upper (ends may be ±∞). */
    void
    set_interval(const unsigned int i, const double lower, const double upper);

    /** Makes component i the lower bound x_i ≥ lower (the interval [lower, +∞)). */
    void
    set_lower_bound(const unsigned int i, const double lower);

    /**
     * Makes components (i, j) the disc block ‖(x_i, x_j) − centre‖ ≤ radius and returns its
     * number k (0, 1, … in order of addition). Both components must still be free.
     */
    unsigned int
    add_disc(const unsigned int           i,
             const unsigned int           j,
             const std::array<double, 2> &centre,
             const double                 radius);

    /** Changes the radius r ≥ 0 of disc k (in MSA: the slip bound g_k = μ λ_N,k). */
    void
    set_disc_radius(const unsigned int k, const double radius);

    /** Changes the centre of disc k. */
    void
    set_disc_centre(const unsigned int k, const double c1, const double c2);

    /** The number of disc blocks. */
    unsigned int
    n_discs() const;

    /** The components (i, j) of disc k. */
    std::array<unsigned int, 2>
    disc_components(const unsigned int k) const;

    /** The centre of disc k. */
    std::array<double, 2>
    disc_centre(const unsigned int k) const;

    /** The radius of disc k. */
    double
    disc_radius(const unsigned int k) const;

    /**
     * x ← P_Ω(x), the Euclidean projection, block by block: intervals clamp; a disc maps y
     * outside to c + r (y − c)/‖y − c‖.
     */
    template <typename VectorType>
    void
    project(VectorType &x) const;

    /**
     * How the tangent directions of active discs are treated by free_gradient(),
     * chopped_gradient() and max_feasible_step().
     *  - `fixed` (MPGP of Dostál–Kozubek, Kučera's KPG): an active disc is an active block; its
     *    gradient goes into β, conjugate gradient steps do not move it.
     *  - `rotations`: an active disc may move along its circle. Its tangential gradient is part
     *    of φ (conjugate gradient steps rotate the block along the arc, projected back onto the
     *    circle), and β keeps only the inward normal part max(g·ν, 0) ν (releasing the block into
     *    the interior is a straight, feasible line). An active disc then never limits a step.
     */
    enum class DiscMode : unsigned char
    {
      fixed,
      rotations
    };

    /**
     * φ(x): the free gradient, g on the components of blocks where x is not on the boundary
     * (free components, interior of intervals and discs), 0 on active blocks; with
     * DiscMode::rotations the tangential part g − (g·ν)ν on active discs with r > 0.
     */
    template <typename VectorType>
    void
    free_gradient(const VectorType &x,
                  const VectorType &g,
                  VectorType       &phi,
                  const DiscMode    mode = DiscMode::fixed) const;

    /**
     * β(x): the chopped gradient, 0 on inactive blocks; an interval at its lower end
     * min(g_i, 0), at its upper end max(g_i, 0); an active disc with outward unit normal
     * ν = (x − c)/‖x − c‖: β = g − min(g·ν, 0) ν (the part of −g pointing out of the disc is
     * removed), with DiscMode::rotations only the inward part max(g·ν, 0) ν; fixed blocks: 0.
     * In both modes φ + β = g^P and φ·β = 0.
     */
    template <typename VectorType>
    void
    chopped_gradient(const VectorType &x,
                     const VectorType &g,
                     VectorType       &beta,
                     const DiscMode    mode = DiscMode::fixed) const;

    /** g^P(x) = φ(x) + β(x), the projected gradient: zero exactly at a KKT point. */
    template <typename VectorType>
    void
    projected_gradient(const VectorType &x, const VectorType &g, VectorType &gP) const;

    /**
     * The largest α ≥ 0 with x − α d ∈ Ω (x ∈ Ω): the ratio test on intervals, the positive
     * root of ‖x_k − c − α d_k‖ = r on discs, 0 for a fixed block with d ≠ 0 on it;
     * +∞ when no block limits the step. With DiscMode::rotations active discs (r > 0) do not
     * limit the step: the path P_Ω(x − αd) follows their circles.
     */
    template <typename VectorType>
    double
    max_feasible_step(const VectorType &x,
                      const VectorType &d,
                      const DiscMode    mode = DiscMode::fixed) const;

    /**
     * Σ_k σ_k ‖t_k‖²/r_k over the active discs k with r_k > 0, where σ_k = max(−g_k·ν_k, 0) is
     * the multiplier the gradient g presses the block outwards with and t_k the tangential part
     * of d_k. It is what the curvature of the circles adds to the second derivative of f along
     * the projected path: f(P_Ω(x − αd)) = f(x) − α gᵀd + ½α²(dᵀAd + arc_curvature) + O(α³)
     * when d is tangential on the discs pressed outwards.
     */
    template <typename VectorType>
    double
    arc_curvature(const VectorType &x, const VectorType &g, const VectorType &d) const;

    /**
     * Hd ← Hd + C d with C the curvature operator of arc_curvature() (dᵀC d = arc_curvature):
     * σ_k/r_k times the tangential part of d_k on the active discs pressed outwards. A d + C d
     * is the Hessian of f along the circles (the Riemannian Hessian), which conjugates the
     * directions of the rotation steps in MPGP.
     */
    template <typename VectorType>
    void
    add_arc_curvature(const VectorType &x,
                      const VectorType &g,
                      const VectorType &d,
                      VectorType       &Hd) const;

    /**
     * v ← v with its normal part ν(ν·v) removed on every active disc with r > 0: the tangent
     * space of the circles at x (the transport of a search direction to a new iterate).
     */
    template <typename VectorType>
    void
    remove_normal_parts(const VectorType &x, VectorType &v) const;

    /**
     * v_k ← v_k/(1 + σ_k/(r_k a)) on every active disc k with r_k > 0 pressed outwards by g
     * (σ_k = −g_k·ν_k > 0): a diagonal preconditioner for steps along the circles, a the scale
     * of the rest of the Hessian (MPGP passes AdditionalData::arc_scale, by default ‖A‖). With @p
     * exponent ≠ 1 the factor is (1 + σ_k/(r_k a))^(−exponent) (MPGP applies ½ on both sides of a
     * preconditioner in face, D^(−½) M D^(−½), which keeps the product symmetric).
     */
    template <typename VectorType>
    void
    precondition_arcs(const VectorType &x,
                      const VectorType &g,
                      const double      a,
                      VectorType       &v,
                      const double      exponent = 1) const;

    /** Whether v is non-zero on some active disc with r > 0 at x (a step along v rotates it). */
    template <typename VectorType>
    bool
    moves_active_discs(const VectorType &x, const VectorType &v) const;

    /** Whether some disc block has a non-zero component of v (MPGP: β acts on a disc). */
    template <typename VectorType>
    bool
    nonzero_on_discs(const VectorType &v) const;

    /**
     * The support function σ_Ω(w) = sup_{x∈Ω} xᵀw: per interval u w_i (w_i > 0) or l w_i
     * (w_i < 0), per disc cᵀw_k + r‖w_k‖; +∞ when a free component, an infinite interval end or
     * an infinite radius meets a non-zero w. Components with |w_i| ≤ zero · ‖w‖_∞ count as 0 (the
     * rounding of a w computed as Gᵀα). With it a vector α proves that Gλ = e has no solution in
     * Ω when αᵀe > σ_Ω(Gᵀα) (SMALBE's infeasibility certificate).
     */
    template <typename VectorType>
    double
    support(const VectorType &w, const double zero = 0) const;

    /**
     * The largest violation of a block constraint: max(l − x_i, x_i − u, ‖x_k − c‖ − r, 0) over
     * all blocks (an absolute number, for tests).
     */
    template <typename VectorType>
    double
    largest_violation(const VectorType &x) const;

    /** x ∈ Ω up to largest_violation(x) ≤ relative_tolerance · ‖x‖_∞. */
    template <typename VectorType>
    bool
    is_feasible(const VectorType &x, const double relative_tolerance) const;

  private:
    enum class Kind : unsigned char
    {
      free,
      interval,
      disc
    };

    struct Disc
    {
      unsigned int          i, j;
      std::array<double, 2> centre;
      double                radius;
    };

    /** Interval state of component i at value v: 0 inside, −1 at the lower end, +1 at the
     * upper end, 2 fixed (l = u, or u − l within twice the activity tolerance). */
    int
    interval_state(const unsigned int i, const double v) const;

    /** Whether disc d is active at x (on its boundary, or r = 0). */
    template <typename VectorType>
    bool
    disc_active(const Disc &d, const VectorType &x) const;

    /** ν = (x − c)/‖x − c‖ of disc d (d active with r > 0, so x ≠ c). */
    template <typename VectorType>
    std::array<double, 2>
    outward_normal(const Disc &d, const VectorType &x) const;

    std::vector<Kind>   kind;
    std::vector<double> lower, upper, scale;
    /** The interval components, increasing. Most components of a FETI dual vector are free
     * (the gluing multipliers): the loops of the projection and of the gradient splittings run
     * over these and the discs only. */
    std::vector<unsigned int> intervals;
    std::vector<Disc>         discs;
  };
} // namespace FetiContact::QP
