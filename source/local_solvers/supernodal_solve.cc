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
    /**
     * The supernodes of L in CHOLMOD's layout: supernode s has the columns super[s] …
     * super[s+1] − 1 and the rows Ls[pi[s]] … Ls[pi[s+1] − 1] (the first ones its own columns);
     * its values are a column-major block of pi[s+1] − pi[s] rows at Lx + px[s].
     */
    struct Supernodes
    {
      explicit Supernodes(const cholmod_factor &L)
        : n(L.nsuper)
        , super(static_cast<const int *>(L.super))
        , pi(static_cast<const int *>(L.pi))
        , px(static_cast<const int *>(L.px))
        , Ls(static_cast<const int *>(L.s))
        , Lx(static_cast<const double *>(L.x))
      {}
      std::size_t   n;
      const int    *super, *pi, *px, *Ls;
      const double *Lx;
    };

    /** y ← L⁻¹ y; t holds the rows of one supernode. */
    FETICONTACT_KERNEL void
    forward(const Supernodes &S, double *y, double *t)
    {
      for (std::size_t s = 0; s < S.n; ++s)
        {
          const int     first = S.super[s], n_columns = S.super[s + 1] - first;
          const int     n_rows = S.pi[s + 1] - S.pi[s];
          const int    *rows   = S.Ls + S.pi[s];
          const double *block  = S.Lx + S.px[s];
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
    backward(const Supernodes &S, double *y, double *t)
    {
      for (std::size_t s = S.n; s-- > 0;)
        {
          const int     first = S.super[s], n_columns = S.super[s + 1] - first;
          const int     n_rows = S.pi[s + 1] - S.pi[s];
          const int    *rows   = S.Ls + S.pi[s];
          const double *block  = S.Lx + S.px[s];
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

  SupernodalSolve::SupernodalSolve(const cholmod_factor &L)
    : L(L)
  {
    require(L.is_super && L.is_ll && L.itype == CHOLMOD_INT && L.xtype == CHOLMOD_REAL,
            "SupernodalSolve: the factor is not a real supernodal LLᵀ factor with int indices.");
    permuted.resize(L.n);
    const Supernodes S(L);
    int              max_rows = 0;
    for (std::size_t s = 0; s < S.n; ++s)
      max_rows = std::max(max_rows, S.pi[s + 1] - S.pi[s]);
    rows_of_supernode.resize(max_rows);
  }

  void
  SupernodalSolve::solve(double *x) const
  {
    const int       *perm = static_cast<const int *>(L.Perm);
    const Supernodes S(L);
    for (std::size_t k = 0; k < L.n; ++k)
      permuted[k] = x[perm[k]];
    forward(S, permuted.data(), rows_of_supernode.data());
    backward(S, permuted.data(), rows_of_supernode.data());
    for (std::size_t k = 0; k < L.n; ++k)
      x[perm[k]] = permuted[k];
  }
} // namespace FetiContact
