#pragma once

#include <cholmod.h>

#include <cstddef>
#include <vector>

namespace FetiContact
{
  /**
   * The triangular solves with a supernodal Cholesky factor P A Pᵀ = L Lᵀ of CHOLMOD (32-bit
   * indices), written for one right-hand side.
   *
   * In FETI every multiplication by F = B K⁺ Bᵀ makes one solve per subdomain, one right-hand
   * side at a time, and the subdomains are small (2,187 unknowns with 8 × 8 × 8 cubes): most of
   * the factor's 130 or so supernodes have a few columns. CHOLMOD's own solve calls the BLAS
   * (dtrsv and dgemv) twice per supernode, and the calls and OpenBLAS's column-by-column forward
   * substitution inside dtrsv cost more than the arithmetic (doc/local_solvers.md, "The solves
   * inside FETI"). Here each supernode is one pass over its columns, which are contiguous in
   * memory: the forward solve subtracts column j, times the new unknown, from the rows below it
   * (diagonal block and off-diagonal rows in one loop); the backward solve takes the dot product
   * of column j with the known unknowns below it. Both read every stored number of L once.
   *
   * The kernels are compiled for AVX2 and for the baseline instruction set, chosen when the
   * program starts (GCC's target_clones); both do the same operations in the same order (no
   * fused multiply-add, no reassociation), so the results do not depend on the processor's
   * instruction set, nor on which MPI rank solves.
   */
  /**
   * A supernodal factor P A Pᵀ = L Lᵀ in CHOLMOD's layout, by pointers to its arrays (owned
   * elsewhere): supernode k has the columns super[k] … super[k+1] − 1 and the rows
   * s[pi[k]] … s[pi[k+1] − 1] (the first ones its own columns); its numbers are a column-major
   * block of pi[k+1] − pi[k] rows at x + px[k]; perm is P (row k of P A Pᵀ is row perm[k] of A).
   * CHOLMOD's own factor (of()).
   */
  struct SupernodalFactor
  {
    /** The arrays of CHOLMOD's factor @p L (is_super, LLᵀ, int indices). */
    static SupernodalFactor
    of(const cholmod_factor &L);

    /** The largest number of rows of a supernode: the size of solve()'s second work array. */
    std::size_t
    max_supernode_rows() const;

    /** The number of stored numbers of L (px[n_supernodes]). */
    std::size_t
    n_values() const
    {
      return n_supernodes == 0 ? 0 : static_cast<std::size_t>(px[n_supernodes]);
    }

    std::size_t   n = 0, n_supernodes = 0;
    const int    *super = nullptr, *pi = nullptr, *px = nullptr, *s = nullptr, *perm = nullptr;
    const double *x = nullptr;
  };

  /**
   * Overwrites @p x (L.n numbers) by A⁻¹ x = Pᵀ L⁻ᵀ L⁻¹ P x; @p permuted (L.n numbers) and
   * @p rows (L.max_supernode_rows()) are work arrays.
   */
  void
  supernodal_solve(const SupernodalFactor &L, double *x, double *permuted, double *rows);

  /** supernodal_solve() bound to one factor, with its own work arrays. */
  class SupernodalSolve
  {
  public:
    /**
     * Binds to the supernodal factor @p L (is_super, LLᵀ, int indices), which must outlive this
     * object and not change.
     */
    explicit SupernodalSolve(const cholmod_factor &L);

    /** Overwrites @p x (n numbers) by A⁻¹ x = Pᵀ L⁻ᵀ L⁻¹ P x. */
    void
    solve(double *x) const;

    /** The factor solved with. */
    const SupernodalFactor &
    factor() const
    {
      return L;
    }

  private:
    SupernodalFactor            L;
    mutable std::vector<double> permuted, rows_of_supernode;
  };
} // namespace FetiContact
