#pragma once

#include <feticontact/base/json_writer.h>

#include <string>

namespace FetiContact
{
  /**
   * summary.json under construction (doc/summary_json.md): the phases of a run and the
   * postprocessors set their results in it as they come (set()), the end of the run sets the
   * leading members (set_leading(): the outcome, the sizes, how the run was made, the times), and
   * write() writes the file once, the leading members first. A run that stops without
   * equilibrium writes its short form through the same object.
   *
   * It also keeps the verdict of the independent checks (check()): the first quantity of a
   * converged run that exceeds its limit refutes the solution, and check_failure() says why.
   */
  class Summary
  {
  public:
    /** A result of a phase or a postprocessor, written after those set before it. */
    template <typename T>
    Summary &
    set(const std::string &key, const T &value)
    {
      results.set(key, value);
      return *this;
    }

    /** A leading member: written before every result, in the order the leading members are set. */
    template <typename T>
    Summary &
    set_leading(const std::string &key, const T &value)
    {
      leading.set(key, value);
      return *this;
    }

    /** Whether the solver converged: the independent checks only judge a converged solve. */
    void
    set_solver_converged(const bool converged)
    {
      solution_accepted = converged;
    }

    /**
     * The independent check of a converged run: a solution whose @p value (a quantity of
     * summary.json, named by @p key) exceeds @p limit is no solution, whatever the solver's
     * residuals say. The first such check of a converged run sets the member `check_failure`
     * to a message naming @p description, the value, @p key and @p limit, and returns true;
     * every other call returns false.
     */
    bool
    check(const std::string &key,
          const std::string &description,
          const double       value,
          const double       limit);

    /** Why the independent check refused the solution (empty: it did not). */
    const std::string &
    check_failure() const
    {
      return failure_message;
    }

    /** The whole object as JSON text: the leading members, then the results. */
    std::string
    str() const;

  private:
    JsonObject  leading;
    JsonObject  results;
    bool        solution_accepted = false;
    std::string failure_message;
  };
} // namespace FetiContact
