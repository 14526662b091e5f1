#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/vector.h>

#include <feticontact/subdomain/rigid_body_modes.h>

#include <cmath>

namespace FetiContact
{
  using namespace dealii;

  namespace
  {
    /** Orthonormalizes the columns of @p R in place (modified Gram–Schmidt, two passes). */
    void
    orthonormalize_columns(FullMatrix<double> &R)
    {
      const unsigned int n = R.m(), k = R.n();
      for (unsigned int pass = 0; pass < 2; ++pass)
        for (unsigned int j = 0; j < k; ++j)
          {
            for (unsigned int l = 0; l < j; ++l)
              {
                double dot = 0;
                for (unsigned int i = 0; i < n; ++i)
                  dot += R(i, j) * R(i, l);
                for (unsigned int i = 0; i < n; ++i)
                  R(i, j) -= dot * R(i, l);
              }
            double norm = 0;
            for (unsigned int i = 0; i < n; ++i)
              norm += R(i, j) * R(i, j);
            norm = std::sqrt(norm);
            for (unsigned int i = 0; i < n; ++i)
              R(i, j) /= norm;
          }
    }
  } // namespace

  void
  symmetric_eigen(const FullMatrix<double> &A, std::vector<double> &w, FullMatrix<double> &V)
  {
    const unsigned int       n = A.m();
    LAPACKFullMatrix<double> M(n, n);
    M = A;
    // Every eigenvalue lies within ±‖A‖_F.
    const double   bound = 1 + A.frobenius_norm();
    Vector<double> values;
    M.compute_eigenvalues_symmetric(-bound, bound, 0., values, V);
    AssertThrow(values.size() == n,
                ExcMessage("symmetric_eigen: LAPACK found " + std::to_string(values.size()) +
                           " of " + std::to_string(n) + " eigenvalues."));
    w.assign(values.begin(), values.end());
  }

  FullMatrix<double>
  rigid_body_modes(const std::vector<Point<3>>     &points,
                   const std::vector<unsigned int> &components,
                   const std::vector<bool>         &fixed)
  {
    const unsigned int n = points.size();
    Point<3>           centroid;
    for (const auto &p : points)
      centroid += p / n;

    // Columns: translations e_x, e_y, e_z and rotations ω = e_x, e_y, e_z about the centroid:
    // (ω × r)_c for r = x − x̄.
    FullMatrix<double> Q(n, 6);
    for (unsigned int i = 0; i < n; ++i)
      {
        const Tensor<1, 3> r = points[i] - centroid;
        const unsigned int c = components[i];
        Q(i, c)              = 1;
        for (unsigned int a = 0; a < 3; ++a)
          {
            Tensor<1, 3> omega;
            omega[a]    = 1;
            Q(i, 3 + a) = cross_product_3d(omega, r)[c];
          }
      }
    orthonormalize_columns(Q);

    // C = Q_Dᵀ Q_D over the fixed DoFs; its null space gives the motions that vanish there.
    FullMatrix<double> C(6, 6);
    bool               any_fixed = false;
    for (unsigned int i = 0; i < n; ++i)
      if (fixed[i])
        {
          any_fixed = true;
          for (unsigned int a = 0; a < 6; ++a)
            for (unsigned int b = 0; b < 6; ++b)
              C(a, b) += Q(i, a) * Q(i, b);
        }
    if (!any_fixed)
      return Q;

    std::vector<double> w;
    FullMatrix<double>  V;
    symmetric_eigen(C, w, V);
    std::vector<unsigned int> null;
    for (unsigned int a = 0; a < 6; ++a)
      if (w[a] < 1e-10)
        null.push_back(a);

    FullMatrix<double> R(n, null.size());
    for (unsigned int i = 0; i < n; ++i)
      if (!fixed[i])
        for (unsigned int j = 0; j < null.size(); ++j)
          for (unsigned int a = 0; a < 6; ++a)
            R(i, j) += Q(i, a) * V(a, null[j]);
    if (R.n() > 0)
      orthonormalize_columns(R);
    return R;
  }

  std::vector<unsigned int>
  select_kernel_fixing_dofs(const FullMatrix<double> &R_in)
  {
    FullMatrix<double>        R(R_in);
    const unsigned int        n = R.m(), k = R.n();
    std::vector<unsigned int> chosen;
    for (unsigned int step = 0; step < k; ++step)
      {
        unsigned int best      = 0;
        double       best_norm = -1;
        for (unsigned int i = 0; i < n; ++i)
          {
            double norm = 0;
            for (unsigned int j = 0; j < k; ++j)
              norm += R(i, j) * R(i, j);
            // Ties (rows of equal norm, common on symmetric meshes) go to the first row: a
            // later row must be larger beyond rounding, so that the choice, and with it the
            // generalized inverse, does not depend on the units of length.
            if (norm > best_norm * (1 + 1e-10))
              {
                best_norm = norm;
                best      = i;
              }
          }
        chosen.push_back(best);
        // Remove the direction of the chosen row from all rows.
        Vector<double> q(k);
        for (unsigned int j = 0; j < k; ++j)
          q[j] = R(best, j) / std::sqrt(best_norm);
        for (unsigned int i = 0; i < n; ++i)
          {
            double dot = 0;
            for (unsigned int j = 0; j < k; ++j)
              dot += R(i, j) * q[j];
            for (unsigned int j = 0; j < k; ++j)
              R(i, j) -= dot * q[j];
          }
      }
    return chosen;
  }
} // namespace FetiContact
