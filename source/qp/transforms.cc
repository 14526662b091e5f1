#include <deal.II/base/exceptions.h>

#include <feticontact/qp/transforms.h>

#include <memory>

namespace FetiContact::QP
{
  using namespace dealii;

  Orthonormalization::Orthonormalization(const Problem &original, const Factor &factor)
    : original(original)
    , factor(factor)
  {}

  Problem
  Orthonormalization::transformed() const
  {
    Problem        problem(original);
    const Problem &P0 = original;
    const Factor   L  = factor;
    problem.G         = [&P0, L](const Vector<double> &x, Vector<double> &y) {
      P0.G(x, y);
      L.solve_L(y);
    };
    problem.Gt = [&P0, L](const Vector<double> &x, Vector<double> &y) {
      Vector<double> z(x);
      L.solve_Lt(z);
      P0.Gt(z, y);
    };
    problem.e = original.e;
    factor.solve_L(problem.e);
    return problem;
  }

  Vector<double>
  Orthonormalization::recover_multiplier(const Vector<double> &nu_tilde) const
  {
    Vector<double> nu(nu_tilde);
    factor.solve_Lt(nu);
    return nu;
  }

  Homogenization::Homogenization(const Problem &original, const Vector<double> &particular)
    : original(original)
    , lambda0(particular)
  {
    AssertThrow(lambda0.size() == original.size(),
                ExcMessage("Homogenization: λ₀ and h differ in size."));
  }

  Problem
  Homogenization::transformed(const SeparableSet &shifted_set) const
  {
    Problem        problem(original);
    Vector<double> F_lambda0(original.size());
    original.hessian(lambda0, F_lambda0);
    problem.linear_term -= F_lambda0;
    problem.e.reinit(original.e.size());
    problem.set = &shifted_set;
    return problem;
  }

  void
  Homogenization::recover(Vector<double> &lambda) const
  {
    lambda += lambda0;
  }

  const Vector<double> &
  Homogenization::particular_solution() const
  {
    return lambda0;
  }

  ProjectorEnforcement::ProjectorEnforcement(const Problem &homogeneous)
    : homogeneous(homogeneous)
  {
    AssertThrow(homogeneous.e.l2_norm() == 0,
                ExcMessage("ProjectorEnforcement needs the homogenized constraint Gλ = 0 (e = 0); "
                           "shift λ by a particular solution first (Homogenization)."));
    project(homogeneous.linear_term, projected_linear_term);
  }

  void
  ProjectorEnforcement::project(const Vector<double> &x, Vector<double> &y) const
  {
    Vector<double> Gx(homogeneous.e.size());
    homogeneous.G(x, Gx);
    y.reinit(x.size());
    homogeneous.Gt(Gx, y);
    y.sadd(-1., 1., x);
  }

  Problem
  ProjectorEnforcement::transformed() const
  {
    Problem problem(homogeneous);
    problem.linear_term       = projected_linear_term;
    problem.linear_term_scale = homogeneous.linear_term_norm();
    if (homogeneous.e.size() == 0)
      return problem;
    // Work vectors shared by the operators of the transformed problem (one solve at a time).
    struct Work
    {
      Vector<double> Gx, Qx, Px, QFPx;
    };
    const auto     work = std::make_shared<Work>();
    const Problem &P0   = homogeneous;
    const auto     Q    = [work, &P0](const Vector<double> &x, Vector<double> &y) {
      work->Gx.reinit(P0.e.size());
      P0.G(x, work->Gx);
      P0.Gt(work->Gx, y);
    };
    // y = PFP x: Px = x − Qx, y = F Px, y ← y − Q y; Qx stays in the work vectors.
    const auto PFP = [work, Q, &P0](const Vector<double> &x, Vector<double> &y) {
      work->Qx.reinit(x.size());
      Q(x, work->Qx);
      work->Px = x;
      work->Px -= work->Qx;
      P0.hessian(work->Px, y);
      work->QFPx.reinit(x.size());
      Q(y, work->QFPx);
      y -= work->QFPx;
    };
    problem.hessian = PFP;
    // PFP x + ρ Q x with the Qx of PFP.
    problem.augmented_hessian =
      [work, PFP](const double rho, const Vector<double> &x, Vector<double> &y) {
        PFP(x, y);
        y.add(rho, work->Qx);
      };
    return problem;
  }

  void
  ProjectorEnforcement::recover_multiplier(const Vector<double> &r, Vector<double> &nu) const
  {
    Vector<double> Gr(homogeneous.e.size());
    homogeneous.G(r, Gr);
    nu -= Gr;
  }
} // namespace FetiContact::QP
