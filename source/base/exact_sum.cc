#include <feticontact/base/exact_sum.h>

#include <cmath>
#include <limits>

namespace FetiContact
{
  void
  ExactSum::normalize()
  {
    for (unsigned int d = 0; d < n_digits; ++d)
      {
        digit[d] += digit[n_digits + d];
        digit[n_digits + d] = 0;
      }
    for (unsigned int d = 0; d + 1 < n_digits; ++d)
      {
        // Floor division by 2^32 (arithmetic shift), so that the remainder is in [0, 2^32).
        const std::int64_t carry = digit[d] >> 32;
        digit[d] -= carry * (std::int64_t(1) << 32);
        digit[d + 1] += carry;
      }
    n_terms = 0;
  }

  void
  ExactSum::add_special(const double x)
  {
    if (std::isnan(x))
      ++n_special[0];
    else if (x > 0)
      ++n_special[1];
    else
      ++n_special[2];
  }

  void
  ExactSum::add(const ExactSum &other)
  {
    ExactSum copy(other);
    copy.normalize();
    normalize();
    for (unsigned int d = 0; d < n_digits; ++d)
      digit[d] += copy.digit[d];
    for (unsigned int k = 0; k < n_special.size(); ++k)
      n_special[k] += other.n_special[k];
  }

  void
  ExactSum::sum_over_ranks(const MPI_Comm comm)
  {
    // After normalize() every digit is below 2^32 in magnitude but the last, which holds the
    // sign and is below 2^31: the sum of the ranks' digits does not overflow below 2^31 ranks.
    normalize();
    std::array<std::int64_t, n_digits + 3> all;
    std::copy(digit.begin(), digit.begin() + n_digits, all.begin());
    std::copy(n_special.begin(), n_special.end(), all.begin() + n_digits);
    MPI_Allreduce(MPI_IN_PLACE, all.data(), all.size(), MPI_INT64_T, MPI_SUM, comm);
    std::copy(all.begin(), all.begin() + n_digits, digit.begin());
    n_terms = 0;
    std::copy(all.begin() + n_digits, all.end(), n_special.begin());
  }

  void
  ExactSum::sum_over_ranks(std::vector<ExactSum> &sums, const MPI_Comm comm)
  {
    constexpr unsigned int    n = n_digits + 3;
    std::vector<std::int64_t> all(n * sums.size());
    for (unsigned int i = 0; i < sums.size(); ++i)
      {
        ExactSum &s = sums[i];
        s.normalize();
        std::copy(s.digit.begin(), s.digit.begin() + n_digits, all.begin() + n * i);
        std::copy(s.n_special.begin(), s.n_special.end(), all.begin() + n * i + n_digits);
      }
    MPI_Allreduce(MPI_IN_PLACE, all.data(), all.size(), MPI_INT64_T, MPI_SUM, comm);
    for (unsigned int i = 0; i < sums.size(); ++i)
      {
        ExactSum &s = sums[i];
        std::copy(all.begin() + n * i, all.begin() + n * i + n_digits, s.digit.begin());
        std::copy(all.begin() + n * i + n_digits, all.begin() + n * (i + 1), s.n_special.begin());
        s.n_terms = 0;
      }
  }

  double
  ExactSum::value() const
  {
    if (n_special[0] > 0 || (n_special[1] > 0 && n_special[2] > 0))
      return std::numeric_limits<double>::quiet_NaN();
    if (n_special[1] > 0)
      return std::numeric_limits<double>::infinity();
    if (n_special[2] > 0)
      return -std::numeric_limits<double>::infinity();

    ExactSum s(*this);
    s.normalize();
    // The integer Σ digit[d] 2^(32d) in sign and magnitude: the last digit carries the sign.
    const bool negative = s.digit[n_digits - 1] < 0;
    if (negative)
      {
        for (auto &d : s.digit)
          d = -d;
        s.normalize();
      }
    int top = n_digits - 1;
    while (top >= 0 && s.digit[top] == 0)
      --top;
    if (top < 0)
      return 0.;
    // The leading 64 bits (bit positions low … low + 63, counted in units of 2^-1074), with the
    // bits below them folded into the last one (a sticky bit), so that the one rounding of the
    // conversion to double is the rounding of the exact sum.
    const auto digit_bits  = [&](const int d) { return static_cast<std::uint64_t>(s.digit[d]); };
    const int  leading_bit = 32 * top + 63 - __builtin_clzll(digit_bits(top));
    const int  low         = leading_bit - 63;
    const auto bit         = [&](const int k) -> std::uint64_t {
      return k < 0 ? 0 : (digit_bits(k / 32) >> (k % 32)) & 1;
    };
    std::uint64_t leading = 0;
    for (int k = leading_bit; k >= low; --k)
      leading = (leading << 1) | bit(k);
    bool sticky = false;
    if (low > 0)
      {
        for (int d = 0; d < low / 32; ++d)
          sticky |= s.digit[d] != 0;
        sticky |= (digit_bits(low / 32) & ((std::uint64_t(1) << (low % 32)) - 1)) != 0;
      }
    if (sticky)
      leading |= 1;
    const double magnitude = std::ldexp(static_cast<double>(leading), low - 1074);
    return negative ? -magnitude : magnitude;
  }
} // namespace FetiContact
