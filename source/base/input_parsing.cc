#include <deal.II/base/mpi.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/base/mpi_tools.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace FetiContact::InputParsing
{
  using namespace dealii;

  std::string
  trim(const std::string &text)
  {
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos)
      return "";
    const auto last = text.find_last_not_of(" \t\r\n");
    return text.substr(first, last - first + 1);
  }

  std::vector<std::string>
  split(const std::string &text, const char separator)
  {
    std::vector<std::string> pieces;
    std::string::size_type   begin = 0;
    while (begin <= text.size())
      {
        auto end = text.find(separator, begin);
        if (end == std::string::npos)
          end = text.size();
        const std::string piece = trim(text.substr(begin, end - begin));
        if (!piece.empty())
          pieces.push_back(piece);
        begin = end + 1;
      }
    return pieces;
  }

  std::string
  number_text(const double value)
  {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.6g", value);
    return buffer;
  }

  double
  parse_double(const std::string &text, const std::string &what)
  {
    const std::string t   = trim(text);
    char             *end = nullptr;
    errno                 = 0;
    const double value    = std::strtod(t.c_str(), &end);
    // Decimal notation only: strtod also reads hexadecimal numbers (0x10 = 16, 0x1p4 = 16).
    require(!t.empty() && end != nullptr && *end == '\0' &&
              t.find_first_of("xXpP") == std::string::npos,
            (what + ": <" + t + "> is not a number."));
    // strtod reports ERANGE for overflow (±HUGE_VAL) and for underflow (a subnormal or zero).
    require(errno != ERANGE,
            (what + ": <" + t + "> is out of range (a double lies within ±1.8e308, and its " +
             "smallest normal magnitude is 2.2e-308)."));
    require(std::isfinite(value), (what + ": <" + t + "> is not a finite number."));
    return value;
  }

  std::vector<double>
  parse_doubles(const std::string &text, const unsigned int n, const std::string &what)
  {
    const auto pieces = split(text, ',');
    require(pieces.size() == n,
            (what + ": expected " + std::to_string(n) + " comma-separated numbers, got <" +
             trim(text) + ">."));
    std::vector<double> values;
    for (const auto &p : pieces)
      values.push_back(parse_double(p, what));
    return values;
  }

  Point<3>
  parse_point(const std::string &text, const std::string &what)
  {
    const auto v = parse_doubles(text, 3, what);
    return Point<3>(v[0], v[1], v[2]);
  }

  Tensor<1, 3>
  parse_vector(const std::string &text, const std::string &what)
  {
    const auto   v = parse_doubles(text, 3, what);
    Tensor<1, 3> t;
    for (unsigned int d = 0; d < 3; ++d)
      t[d] = v[d];
    return t;
  }

  std::vector<unsigned int>
  parse_positive_integers(const std::string &text, const unsigned int n, const std::string &what)
  {
    const auto pieces = split(text, ',');
    require(pieces.size() == n,
            (what + ": expected " + std::to_string(n) +
             " comma-separated positive integers, got <" + trim(text) + ">."));
    std::vector<unsigned int> values;
    for (const auto &p : pieces)
      {
        char *end    = nullptr;
        errno        = 0;
        const long v = std::strtol(p.c_str(), &end, 10);
        require(*end == '\0' && errno == 0 && v > 0 && v < (1L << 30),
                (what + ": <" + p + "> is not a positive integer."));
        values.push_back(static_cast<unsigned int>(v));
      }
    return values;
  }
} // namespace FetiContact::InputParsing
