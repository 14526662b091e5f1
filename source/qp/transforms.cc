#include <deal.II/base/exceptions.h>

#include <feticontact/base/reproducible_partitioner.h>
#include <feticontact/qp/transforms.h>

#include <memory>

namespace FetiContact::QP
{
  using namespace dealii;

  template <typename VectorType>
  Orthonormalization<VectorType>::Orthonormalization(const Problem<VectorType> &original,
                                                     const Factor              &factor)
    : original(original)
    , factor(factor)
  {}

  template <typename VectorType>
  Problem<VectorType>
  Orthonormalization<VectorType>::transformed() const
  {
    Problem<VectorType>        problem(original);
    const Problem<VectorType> &P0 = original;
    const Factor               L  = factor;
    problem.G                     = [&P0, L](const VectorType &x, Vector<double> &y) {
      P0.G(x, y);
      L.solve_L(y);
    };
    problem.Gt = [&P0, L](const Vector<double> &x, VectorType &y) {
      Vector<double> z(x);
      L.solve_Lt(z);
      P0.Gt(z, y);
    };
    problem.e = original.e;
    factor.solve_L(problem.e);
    return problem;
  }

  template <typename VectorType>
  Vector<double>
  Orthonormalization<VectorType>::recover_multiplier(const Vector<double> &nu_tilde) const
  {
    Vector<double> nu(nu_tilde);
    factor.solve_Lt(nu);
    return nu;
  }

  template <typename VectorType>
  Homogenization<VectorType>::Homogenization(const Problem<VectorType> &original,
                                             const VectorType          &particular)
    : original(original)
    , lambda0(particular)
  {
    AssertThrow(lambda0.size() == original.size(),
                ExcMessage("Homogenization: λ₀ and h differ in size."));
  }

  template <typename VectorType>
  Problem<VectorType>
  Homogenization<VectorType>::transformed(const SeparableSet &shifted_set) const
  {
    Problem<VectorType> problem(original);
    VectorType          F_lambda0;
    F_lambda0.reinit(lambda0);
    original.hessian(lambda0, F_lambda0);
    problem.linear_term -= F_lambda0;
    problem.e.reinit(original.e.size());
    problem.set = &shifted_set;
    return problem;
  }

  template <typename VectorType>
  void
  Homogenization<VectorType>::recover(VectorType &lambda) const
  {
    lambda += lambda0;
  }

  template <typename VectorType>
  const VectorType &
  Homogenization<VectorType>::particular_solution() const
  {
    return lambda0;
  }

  template <typename VectorType>
  ProjectorEnforcement<VectorType>::ProjectorEnforcement(const Problem<VectorType> &homogeneous)
    : homogeneous(homogeneous)
  {
    AssertThrow(homogeneous.e.l2_norm() == 0,
                ExcMessage("ProjectorEnforcement needs the homogenized constraint Gλ = 0 (e = 0); "
                           "shift λ by a particular solution first (Homogenization)."));
    project(homogeneous.linear_term, projected_linear_term);
  }

  template <typename VectorType>
  void
  ProjectorEnforcement<VectorType>::project(const VectorType &x, VectorType &y) const
  {
    Vector<double> Gx(homogeneous.e.size());
    homogeneous.G(x, Gx);
    y.reinit(x);
    homogeneous.Gt(Gx, y);
    y.sadd(-1., 1., x);
  }

  template <typename VectorType>
  Problem<VectorType>
  ProjectorEnforcement<VectorType>::transformed() const
  {
    Problem<VectorType> problem(homogeneous);
    problem.linear_term       = projected_linear_term;
    problem.linear_term_scale = homogeneous.linear_term_norm();
    if (homogeneous.e.size() == 0)
      return problem;
    // Work vectors shared by the operators of the transformed problem (one solve at a time).
    struct Work
    {
      Vector<double> Gx;
      VectorType     Qx, Px, QFPx;
    };
    const auto                 work = std::make_shared<Work>();
    const Problem<VectorType> &P0   = homogeneous;
    const auto                 Q    = [work, &P0](const VectorType &x, VectorType &y) {
      work->Gx.reinit(P0.e.size());
      P0.G(x, work->Gx);
      P0.Gt(work->Gx, y);
    };
    // y = PFP x: Px = x − Qx, y = F Px, y ← y − Q y; Qx stays in the work vectors.
    const auto PFP = [work, Q, &P0](const VectorType &x, VectorType &y) {
      work->Qx.reinit(x);
      Q(x, work->Qx);
      work->Px = x;
      work->Px -= work->Qx;
      P0.hessian(work->Px, y);
      work->QFPx.reinit(x);
      Q(y, work->QFPx);
      y -= work->QFPx;
    };
    problem.hessian = PFP;
    // PFP x + ρ Q x with the Qx of PFP.
    problem.augmented_hessian = [work, PFP](const double rho, const VectorType &x, VectorType &y) {
      PFP(x, y);
      y.add(rho, work->Qx);
    };
    return problem;
  }

  template <typename VectorType>
  void
  ProjectorEnforcement<VectorType>::recover_multiplier(const VectorType &r,
                                                       Vector<double>   &nu) const
  {
    Vector<double> Gr(homogeneous.e.size());
    homogeneous.G(r, Gr);
    nu -= Gr;
  }
  template class Orthonormalization<DistributedVector>;
  template class Homogenization<DistributedVector>;
  template class ProjectorEnforcement<DistributedVector>;
} // namespace FetiContact::QP
