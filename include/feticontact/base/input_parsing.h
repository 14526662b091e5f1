#pragma once

#include <deal.II/base/exceptions.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <functional>
#include <mpi.h>
#include <stdexcept>
#include <string>
#include <vector>

/**
 * Strict parsing of the text values of parameter-file entries. Every function throws an
 * ExcMessage that names the parameter and the offending text, so that a user sees which line of
 * the input is wrong. Non-finite numbers (NaN, inf) are rejected: no physical input is NaN.
 *
 * Entries that are a plain number, integer, flag or choice are declared with deal.II's Patterns
 * and read with ParameterHandler's getters. These functions serve the entries that Patterns
 * cannot describe or whose refusal they cannot word: 'auto' or a number, lists of points and
 * of face predicates, and lists of numbers where the message names the offending item
 * ("<a> is not a positive integer") instead of printing the whole list pattern.
 */
namespace FetiContact
{
  /**
   * An error in what the user gave: the parameter file, a mesh file, or a scene that cannot be
   * solved as posed (a body that nothing holds, …). The message names the cause; the program
   * prints it and exits with a non-zero status.
   */
  class InputError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /** Throws InputError(@p message) unless @p condition holds. */
  inline void
  require(const bool condition, const std::string &message)
  {
    if (!condition)
      throw InputError(message);
  }
} // namespace FetiContact

namespace FetiContact::InputParsing
{
  /** Trims white space on both ends. */
  std::string
  trim(const std::string &text);

  /** Splits @p text at every @p separator and trims the pieces; empty pieces are dropped. */
  std::vector<std::string>
  split(const std::string &text, const char separator);

  /**
   * A number for a message: six significant digits, in scientific notation when it is small or
   * large (printf's %g: 3.5e-07, 0.25, 2.1e+11), so that no value prints as 0.000000.
   */
  std::string
  number_text(const double value);

  /**
   * One finite real number; @p what names the parameter for the error message. A number beyond
   * the range of double (1e400, 1e-400) is "out of range".
   */
  double
  parse_double(const std::string &text, const std::string &what);

  /** A comma-separated list of exactly @p n finite reals. */
  std::vector<double>
  parse_doubles(const std::string &text, const unsigned int n, const std::string &what);

  /** A comma-separated list of three finite reals as a point. */
  dealii::Point<3>
  parse_point(const std::string &text, const std::string &what);

  /** A comma-separated list of three finite reals as a vector (force, traction, …). */
  dealii::Tensor<1, 3>
  parse_vector(const std::string &text, const std::string &what);

  /** A comma-separated list of exactly @p n positive integers. */
  std::vector<unsigned int>
  parse_positive_integers(const std::string &text, const unsigned int n, const std::string &what);
} // namespace FetiContact::InputParsing
