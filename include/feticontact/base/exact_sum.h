#pragma once

#include <array>
#include <cstdint>
#include <mpi.h>
#include <vector>

namespace FetiContact
{
  /**
   * The exact sum of floating-point numbers, rounded once: a sum that does not depend on the
   * order of its terms, nor on how they are split among MPI ranks.
   *
   * Floating-point addition is not associative, so a dot product of a vector distributed over
   * ranks (local sums, then MPI_Allreduce) changes in its last bits with the number of ranks, and
   * an active-set solver's iterates and iteration counts with it. Here every term x (a finite
   * double) is added exactly into a fixed-point accumulator that covers the whole range of
   * doubles: x = m 2^(s − 1074) with an integer m < 2^53 and a shift 0 ≤ s ≤ 2045, and m 2^s
   * goes into 32-bit digits held in 64-bit integers (66 digits and one for carries). Integer
   * addition is associative, so the accumulators of the ranks add up (sum_over_ranks(), one
   * MPI_Allreduce of 536 bytes) to the same integers whatever the order, and value() rounds that
   * exact sum to the nearest double (ties to even; a result in the subnormal range may be off
   * by one unit in its last place). Infinite and NaN terms give the IEEE result of adding them.
   *
   * A term costs a few integer operations (about three times a plain addition).
   */
  class ExactSum
  {
  public:
    /** Adds the term @p x exactly. */
    void
    add(const double x)
    {
      std::uint64_t bits;
      static_assert(sizeof(bits) == sizeof(x));
      __builtin_memcpy(&bits, &x, sizeof(x));
      const unsigned int biased = (bits >> 52) & 0x7ff;
      if (biased == 0x7ff)
        return add_special(x);
      std::uint64_t mantissa = bits & ((std::uint64_t(1) << 52) - 1);
      if (mantissa == 0 && biased == 0)
        return;
      if (biased > 0)
        mantissa |= std::uint64_t(1) << 52;
      const unsigned int shift = biased > 0 ? biased - 1 : 0;
      const unsigned int d     = shift / 32;
      // m 2^r with r = shift mod 32 < 32 spans three digits (m 2^r < 2^85).
      const unsigned int r    = shift % 32;
      const std::int64_t low  = static_cast<std::int64_t>((mantissa << r) & 0xffffffffu),
                         mid  = static_cast<std::int64_t>((mantissa >> (32 - r)) & 0xffffffffu),
                         high = r == 0 ? 0 : static_cast<std::int64_t>(mantissa >> (64 - r));
      // Negative terms subtract: (v ^ s) − s with s = 0 or −1, without a branch (the signs of
      // the products of a dot product are random).
      // Successive terms go to alternate lanes: two chains of additions to memory instead of one.
      const std::int64_t sign = -static_cast<std::int64_t>(bits >> 63);
      std::int64_t      *lane = digit.data() + (n_terms & 1) * n_digits;
      lane[d] += (low ^ sign) - sign;
      lane[d + 1] += (mid ^ sign) - sign;
      lane[d + 2] += (high ^ sign) - sign;
      if (++n_terms == carry_interval)
        normalize();
    }

    /** Adds the product a b (rounded to a double first, then added exactly). */
    void
    add_product(const double a, const double b)
    {
      add(a * b);
    }

    /** Adds the terms of another sum exactly. */
    void
    add(const ExactSum &other);

    /** Makes this the exact sum of the terms of all ranks of @p comm. Collective. */
    void
    sum_over_ranks(const MPI_Comm comm);

    /** sum_over_ranks() of every sum of @p sums, in one reduction. Collective. */
    static void
    sum_over_ranks(std::vector<ExactSum> &sums, const MPI_Comm comm);

    /** The sum rounded to the nearest double. */
    double
    value() const;

  private:
    /** The number of 32-bit digits: 2045 + 85 bits, and one more for carries. */
    static constexpr unsigned int n_digits = 68;
    /** Terms between two carry propagations (a digit then stays below 2^62 in magnitude). */
    static constexpr unsigned int carry_interval = 1u << 29;

    /** Adds the second lane to the first and propagates the carries: every digit of the first
     * lane but the last to [0, 2^32). */
    void
    normalize();

    /** Adds an infinite or NaN term. */
    void
    add_special(const double x);

    /** Two lanes of digits (terms alternate between them; normalize() adds them up). */
    std::array<std::int64_t, 2 * n_digits> digit{};
    /** The numbers of NaN, +∞ and −∞ terms. */
    std::array<std::int64_t, 3> n_special{};
    unsigned int                n_terms = 0;
  };
} // namespace FetiContact
