#include <feticontact/base/input_parsing.h>
#include <feticontact/core/summary.h>

namespace FetiContact
{
  bool
  Summary::check(const std::string &key,
                 const std::string &description,
                 const double       value,
                 const double       limit)
  {
    if (!solution_accepted || value <= limit)
      return false;
    solution_accepted = false;
    failure_message   = "the solver's residuals are small, but the independent check finds " +
                      description + " " + InputParsing::number_text(value) + " (" + key +
                      ", limit " + InputParsing::number_text(limit) + ")";
    set("check_failure", failure_message);
    return true;
  }

  std::string
  Summary::str() const
  {
    JsonObject whole = leading;
    return whole.append(results).str();
  }
} // namespace FetiContact
