#include <feticontact/qp/projected_cg.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace FetiContact::QP
{
  using namespace dealii;

  SolverReport
  projected_conjugate_gradient(
    const std::function<void(const Vector<double> &, Vector<double> &)> &A,
    const std::function<void(Vector<double> &)>                         &P,
    const Vector<double>                                                &b,
    Vector<double>                                                      &x,
    const double                                                         tolerance,
    const unsigned int                                                   max_iterations,
    const std::function<void(unsigned int, double)>                     &monitor,
    const std::function<void(const Vector<double> &, Vector<double> &)> &M)
  {
    SolverReport   report;
    Vector<double> g(b.size()), w(b.size()), p(b.size()), Ap(b.size()), z(b.size());
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
    Vector<double> Pb(b), Ax(b.size());
    P(Pb);
    A(x, Ax);
    ++report.hessian_multiplications;
    const double noise = 64 * std::numeric_limits<double>::epsilon() * (b.l2_norm() + Ax.l2_norm());
    const double reference = std::max(Pb.l2_norm(), noise / tolerance);
    if (reference == 0)
      {
        report.converged = true;
        return report;
      }

    precondition();
    double wz = w * z;
    // ‖w‖ (without a preconditioner w·z = ‖w‖², evaluated as before).
    const auto w_norm        = [&]() { return M ? w.l2_norm() : std::sqrt(wz); };
    report.relative_residual = w_norm() / reference;
    p                        = z;
    while (report.relative_residual > tolerance)
      {
        if (report.iterations >= max_iterations)
          return report;
        A(p, Ap);
        ++report.hessian_multiplications;
        const double pAp = p * Ap;
        if (!(pAp > 0))
          return report; // breakdown: A not positive definite on range(P)
        const double alpha = wz / pAp;
        x.add(-alpha, p);
        g.add(-alpha, Ap);
        w = g;
        P(w);
        precondition();
        const double wz_new = w * z;
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
} // namespace FetiContact::QP
