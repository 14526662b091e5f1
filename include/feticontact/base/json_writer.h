#pragma once

#include <string>
#include <utility>
#include <vector>

namespace FetiContact
{
  /**
   * A JSON object written in the order its members are set: the machine-readable summary of a
   * run (summary.json). Numbers keep 17 significant digits; NaN and infinities become null.
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

    /** Appends all members of @p other. */
    JsonObject &
    append(const JsonObject &other);

    /** The object as text, members indented by @p indent spaces per level. */
    std::string
    str(const unsigned int indent = 2, const unsigned int level = 0) const;

  private:
    /** Members: key, and value as JSON text (objects are kept to be indented when written). */
    std::vector<std::pair<std::string, std::string>> members;
    std::vector<std::pair<std::string, JsonObject>>  objects;
    std::vector<int>                                 object_index;
  };
} // namespace FetiContact
