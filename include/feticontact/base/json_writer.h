#pragma once

#include <string>
#include <utility>
#include <vector>

namespace FetiContact
{
  /**
   * A JSON object written in the order its members are set: the machine-readable summary of a
   * run (summary.json). Numbers keep 17 significant digits; NaN and infinities become null;
   * strings are escaped (quotes, backslashes, control characters). Keys are unique: setting a
   * key twice is a programming error (std::logic_error), so that no reader drops a member.
   */
  class JsonObject
  {
  public:
    JsonObject &
    set(const std::string &key, const double value);
    JsonObject &
    set(const std::string &key, const int value);
    JsonObject &
    set(const std::string &key, const unsigned int value);
    JsonObject &
    set(const std::string &key, const bool value);
    JsonObject &
    set(const std::string &key, const std::string &value);
    JsonObject &
    set(const std::string &key, const char *value);
    JsonObject &
    set(const std::string &key, const std::vector<double> &values);
    JsonObject &
    set(const std::string &key, const JsonObject &object);
    /** An array of objects (records with keys of their own, e.g. one per body). */
    JsonObject &
    set(const std::string &key, const std::vector<JsonObject> &objects);

    /** Appends all members of @p other. */
    JsonObject &
    append(const JsonObject &other);

    /** The object as text, members indented by @p indent spaces per level. */
    std::string
    str(const unsigned int indent = 2, const unsigned int level = 0) const;

  private:
    /** Throws std::logic_error if @p key is a member already. */
    void
    add_key(const std::string &key);

    /** Members: key, and value as JSON text (objects are kept to be indented when written). */
    std::vector<std::pair<std::string, std::string>> members;
    std::vector<std::pair<std::string, JsonObject>>  objects;
    /** Per member: −1 plain text, ≥ 0 an index into objects, ≤ −2 the array −2 − index. */
    std::vector<int>                     object_index;
    std::vector<std::vector<JsonObject>> arrays;
  };
} // namespace FetiContact
