#include <feticontact/base/input_parsing.h>
#include <feticontact/qp/projected_cg.h>
#include <feticontact/qp/vector_reductions.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace FetiContact::QP
{
  using namespace dealii;

  void
  ProjectedCGParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Relative tolerance",
                      "1e-10",
                      Patterns::Double(0, 1),
                      "Projected CG stops when the projected dual gradient has dropped below "
                      "this fraction of its value at λ = 0: ‖P(Fλ − h)‖ ≤ tol ‖P h‖.");
    prm.declare_entry("Maximum iterations",
                      "5000",
                      Patterns::Integer(1),
                      "Largest number of projected CG iterations.");
  }

  void
  ProjectedCGParameters::parse_parameters(ParameterHandler &prm)
  {
    tolerance = prm.get_double("Relative tolerance");
    require(tolerance > 0,
            "FETI/Relative tolerance must be positive; got " + prm.get("Relative tolerance"));
    max_iterations = prm.get_integer("Maximum iterations");
  }

  namespace
  {
    /**
     * Stagnation of a residual sequence r_k: true once the least value has not halved for
     * max(100, k/4) iterations. CG's residuals oscillate and have plateaus, but a factor of two
     * over a quarter of the iterations so far is progress that a residual above its rounding
     * floor makes.
     */
    class StagnationWatch
    {
    public:
      bool
      stagnated(const unsigned int k, const double residual)
      {
        if (residual < best / 2)
          {
            best           = residual;
            best_iteration = k;
          }
        return k - best_iteration >= std::max(100u, k / 4);
      }

    private:
      double       best           = std::numeric_limits<double>::infinity();
      unsigned int best_iteration = 0;
    };
  } // namespace

  template <typename VectorType>
  ProjectedCG<VectorType>::ProjectedCG()
    : additional_data()
  {}

  template <typename VectorType>
  ProjectedCG<VectorType>::ProjectedCG(const AdditionalData &data)
    : additional_data(data)
  {}

  template <typename VectorType>
  SolverReport
  ProjectedCG<VectorType>::solve(const Operator                                  &A,
                                 const Projector                                 &P,
                                 const VectorType                                &b,
                                 VectorType                                      &x,
                                 const std::function<void(unsigned int, double)> &monitor,
                                 const Operator                                  &M) const
  {
    const double       tolerance      = additional_data.tolerance;
    const unsigned int max_iterations = additional_data.max_iterations;
    SolverReport       report;
    VectorType         g, w, p, Ap, z;
    for (auto *v : {&g, &w, &p, &Ap, &z})
      v->reinit(b);
    // z = P M w (w itself without a preconditioner).
    const auto precondition = [&]() {
      if (M)
        {
          M(w, z);
          P(z);
        }
      else
        z = w;
    };

    // g = Ax − b, w = Pg.
    A(x, g);
    ++report.hessian_multiplications;
    g -= b;
    w = g;
    P(w);

    // Reference: ‖Pb‖, but not below what rounding leaves in the data: when Pb vanishes up to
    // rounding (x₀ is already the solution), a gradient at the noise level counts as zero.
    VectorType Pb(b), Ax;
    Ax.reinit(b);
    P(Pb);
    A(x, Ax);
    ++report.hessian_multiplications;
    const double noise = 64 * std::numeric_limits<double>::epsilon() * (l2_norm(b) + l2_norm(Ax));
    const double reference = std::max(l2_norm(Pb), noise / tolerance);
    if (reference == 0)
      {
        report.converged = true;
        return report;
      }

    precondition();
    double wz = dot(w, z);
    // ‖w‖ (without a preconditioner w·z = ‖w‖², evaluated as before).
    const auto w_norm        = [&]() { return M ? l2_norm(w) : std::sqrt(wz); };
    report.relative_residual = w_norm() / reference;
    p                        = z;
    StagnationWatch watch;
    while (report.relative_residual > tolerance)
      {
        if (watch.stagnated(report.iterations, report.relative_residual))
          {
            // The recursive residual has reached its floor: measure the true one at x.
            A(x, g);
            ++report.hessian_multiplications;
            g -= b;
            w = g;
            P(w);
            report.relative_residual = l2_norm(w) / reference;
            report.converged         = report.relative_residual <= tolerance;
            report.stagnated         = !report.converged;
            return report;
          }
        if (report.iterations >= max_iterations)
          return report;
        A(p, Ap);
        ++report.hessian_multiplications;
        const double pAp = dot(p, Ap);
        if (!(pAp > 0))
          return report; // breakdown: A not positive definite on range(P)
        const double alpha = wz / pAp;
        x.add(-alpha, p);
        g.add(-alpha, Ap);
        w = g;
        P(w);
        precondition();
        const double wz_new = dot(w, z);
        p.sadd(wz_new / wz, 1.0, z);
        wz = wz_new;
        ++report.iterations;
        report.relative_residual = w_norm() / reference;
        if (monitor)
          monitor(report.iterations, report.relative_residual);
      }
    report.converged = true;
    return report;
  }
  template class ProjectedCG<DistributedVector>;
} // namespace FetiContact::QP
