#pragma once

// Random test problems for the QP solvers (shared by qp_mpgp.cc and qp_smalbe.cc).

#include <deal.II/lac/full_matrix.h>

#include <cmath>
#include <limits>
#include <random>

namespace QPTestProblems
{
  using namespace dealii;

  const double infinity = std::numeric_limits<double>::infinity();

  std::mt19937                           random_engine(7);
  std::uniform_real_distribution<double> uniform(-1, 1);

  double
  random_in(const double a, const double b)
  {
    return a + (b - a) * (uniform(random_engine) + 1) / 2;
  }

  /** A = Q diag(λ) Qᵀ, Q orthogonal (Gram–Schmidt of a random matrix), λ log-spaced in
   * [1, condition]. */
  FullMatrix<double>
  random_spd(const unsigned int n, const double condition)
  {
    FullMatrix<double> Q(n, n), A(n, n);
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        Q(i, j) = uniform(random_engine);
    for (unsigned int j = 0; j < n; ++j)
      for (unsigned int pass = 0; pass < 2; ++pass)
        {
          for (unsigned int l = 0; l < j; ++l)
            {
              double s = 0;
              for (unsigned int i = 0; i < n; ++i)
                s += Q(i, j) * Q(i, l);
              for (unsigned int i = 0; i < n; ++i)
                Q(i, j) -= s * Q(i, l);
            }
          double s = 0;
          for (unsigned int i = 0; i < n; ++i)
            s += Q(i, j) * Q(i, j);
          for (unsigned int i = 0; i < n; ++i)
            Q(i, j) /= std::sqrt(s);
        }
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        {
          double s = 0;
          for (unsigned int l = 0; l < n; ++l)
            s += Q(i, l) * std::pow(condition, double(l) / (n - 1)) * Q(j, l);
          A(i, j) = s;
        }
    return A;
  }

} // namespace QPTestProblems
