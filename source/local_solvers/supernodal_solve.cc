#include <feticontact/base/input_parsing.h>
#include <feticontact/local_solvers/supernodal_solve.h>

#include <algorithm>
#include <cstddef>

// The kernels are worth vectorizing (the inner loops run over the rows of a supernode); the
// build's -O2 does not, so they carry their own optimization level and an AVX2 variant.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#  define FETICONTACT_KERNEL __attribute__((target_clones("avx2", "default"), optimize("O3")))
#else
#  define FETICONTACT_KERNEL
#endif

namespace FetiContact
{
  namespace
  {
    /** y ← L⁻¹ y; t holds the rows of one supernode. */
    FETICONTACT_KERNEL void
    forward(const SupernodalFactor &S, double *y, double *t)
    {
      for (std::size_t s = 0; s < S.n_supernodes; ++s)
        {
          const int     first = S.super[s], n_columns = S.super[s + 1] - first;
          const int     n_rows = S.pi[s + 1] - S.pi[s];
          const int    *rows   = S.s + S.pi[s];
          const double *block  = S.x + S.px[s];
          for (int i = 0; i < n_rows; ++i)
            t[i] = y[rows[i]];
          for (int j = 0; j < n_columns; ++j)
            {
              const double *column = block + std::size_t(j) * n_rows;
              const double  x_j    = t[j] / column[j];
              t[j]                 = x_j;
              for (int i = j + 1; i < n_rows; ++i)
                t[i] -= column[i] * x_j;
            }
          for (int i = 0; i < n_rows; ++i)
            y[rows[i]] = t[i];
        }
    }

    /** y ← L⁻ᵀ y; t holds the rows of one supernode. */
    FETICONTACT_KERNEL void
    backward(const SupernodalFactor &S, double *y, double *t)
    {
      for (std::size_t s = S.n_supernodes; s-- > 0;)
        {
          const int     first = S.super[s], n_columns = S.super[s + 1] - first;
          const int     n_rows = S.pi[s + 1] - S.pi[s];
          const int    *rows   = S.s + S.pi[s];
          const double *block  = S.x + S.px[s];
          for (int i = n_columns; i < n_rows; ++i)
            t[i] = y[rows[i]];
          for (int j = n_columns - 1; j >= 0; --j)
            {
              // Four partial sums in a fixed order: the same numbers with or without AVX2.
              const double *column = block + std::size_t(j) * n_rows;
              double        a0 = 0, a1 = 0, a2 = 0, a3 = 0;
              int           i = j + 1;
              for (; i + 3 < n_rows; i += 4)
                {
                  a0 += column[i] * t[i];
                  a1 += column[i + 1] * t[i + 1];
                  a2 += column[i + 2] * t[i + 2];
                  a3 += column[i + 3] * t[i + 3];
                }
              for (; i < n_rows; ++i)
                a0 += column[i] * t[i];
              t[j] = (y[first + j] - ((a0 + a1) + (a2 + a3))) / column[j];
            }
          for (int j = 0; j < n_columns; ++j)
            y[first + j] = t[j];
        }
    }
  } // namespace

  SupernodalFactor
  SupernodalFactor::of(const cholmod_factor &L)
  {
    require(L.is_super && L.is_ll && L.itype == CHOLMOD_INT && L.xtype == CHOLMOD_REAL,
            "SupernodalSolve: the factor is not a real supernodal LLᵀ factor with int indices.");
    SupernodalFactor f;
    f.n            = L.n;
    f.n_supernodes = L.nsuper;
    f.super        = static_cast<const int *>(L.super);
    f.pi           = static_cast<const int *>(L.pi);
    f.px           = static_cast<const int *>(L.px);
    f.s            = static_cast<const int *>(L.s);
    f.perm         = static_cast<const int *>(L.Perm);
    f.x            = static_cast<const double *>(L.x);
    return f;
  }

  std::size_t
  SupernodalFactor::max_supernode_rows() const
  {
    int max_rows = 0;
    for (std::size_t k = 0; k < n_supernodes; ++k)
      max_rows = std::max(max_rows, pi[k + 1] - pi[k]);
    return max_rows;
  }

  void
  supernodal_solve(const SupernodalFactor &L, double *x, double *permuted, double *rows)
  {
    for (std::size_t k = 0; k < L.n; ++k)
      permuted[k] = x[L.perm[k]];
    forward(L, permuted, rows);
    backward(L, permuted, rows);
    for (std::size_t k = 0; k < L.n; ++k)
      x[L.perm[k]] = permuted[k];
  }

  SupernodalSolve::SupernodalSolve(const cholmod_factor &factor)
    : L(SupernodalFactor::of(factor))
    , permuted(L.n)
    , rows_of_supernode(L.max_supernode_rows())
  {}

  void
  SupernodalSolve::solve(double *x) const
  {
    supernodal_solve(L, x, permuted.data(), rows_of_supernode.data());
  }
} // namespace FetiContact
