#pragma once

// Random test problems for the QP solvers (shared by qp_mpgp.cc, qp_smalbe.cc, projected_cg.cc
// and distributed_qp.cc), and products of a FullMatrix with the QP vectors on one process.

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <feticontact/base/reproducible_partitioner.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

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

  /**
   * w = A v for the vectors of the QP layer on one process: DistributedVector (global index =
   * local index) or the coarse dealii::Vector<double>, in either role. w keeps its layout (the
   * QP layer passes it sized); every entry is overwritten.
   */
  template <typename InVector, typename OutVector>
  void
  multiply(const FullMatrix<double> &A, const InVector &v, OutVector &w)
  {
    AssertDimension(v.size(), A.n());
    AssertDimension(w.size(), A.m());
    for (unsigned int i = 0; i < A.m(); ++i)
      {
        double s = 0;
        for (unsigned int j = 0; j < A.n(); ++j)
          s += A(i, j) * v(j);
        w(i) = s;
      }
  }

  /** w = Aᵀ v (as multiply()). */
  template <typename InVector, typename OutVector>
  void
  multiply_transposed(const FullMatrix<double> &A, const InVector &v, OutVector &w)
  {
    AssertDimension(v.size(), A.m());
    AssertDimension(w.size(), A.n());
    for (unsigned int j = 0; j < A.n(); ++j)
      {
        double s = 0;
        for (unsigned int i = 0; i < A.m(); ++i)
          s += A(i, j) * v(i);
        w(j) = s;
      }
  }

  /** A vector on one process from a list of numbers. */
  inline FetiContact::DistributedVector
  vec(const std::vector<double> &v)
  {
    FetiContact::DistributedVector x(v.size());
    for (unsigned int i = 0; i < x.locally_owned_size(); ++i)
      x.local_element(i) = v[i];
    return x;
  }

  /** Whether a and b have the same size and the same entries (exactly; one process). */
  inline bool
  same_entries(const FetiContact::DistributedVector &a, const FetiContact::DistributedVector &b)
  {
    if (a.size() != b.size() || a.locally_owned_size() != b.locally_owned_size())
      return false;
    for (unsigned int i = 0; i < a.locally_owned_size(); ++i)
      if (a.local_element(i) != b.local_element(i))
        return false;
    return true;
  }
} // namespace QPTestProblems
