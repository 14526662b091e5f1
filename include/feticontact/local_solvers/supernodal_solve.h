#pragma once

#include <cholmod.h>

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

  private:
    const cholmod_factor       &L;
    mutable std::vector<double> permuted, rows_of_supernode;
  };
} // namespace FetiContact
