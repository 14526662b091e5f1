#include <feticontact/base/json_writer.h>

#include <cmath>
#include <cstdio>

namespace FetiContact
{
  namespace
  {
    std::string
    number(const double v)
    {
      if (!std::isfinite(v))
        return "null";
      char buffer[64];
      std::snprintf(buffer, sizeof(buffer), "%.17g", v);
      return buffer;
    }

    std::string
    quoted(const std::string &s)
    {
      std::string out = "\"";
      for (const char c : s)
        {
          if (c == '"' || c == '\\')
            out += '\\';
          if (c == '\n')
            {
              out += "\\n";
              continue;
            }
          out += c;
        }
      return out + "\"";
    }
  } // namespace

  JsonObject &
  JsonObject::set(const std::string &key, const double value)
  {
    members.emplace_back(key, number(value));
    object_index.push_back(-1);
    return *this;
  }

  JsonObject &
  JsonObject::set(const std::string &key, const int value)
  {
    members.emplace_back(key, std::to_string(value));
    object_index.push_back(-1);
    return *this;
  }

  JsonObject &
  JsonObject::set(const std::string &key, const unsigned int value)
  {
    members.emplace_back(key, std::to_string(value));
    object_index.push_back(-1);
    return *this;
  }

  JsonObject &
  JsonObject::set(const std::string &key, const bool value)
  {
    members.emplace_back(key, value ? "true" : "false");
    object_index.push_back(-1);
    return *this;
  }

  JsonObject &
  JsonObject::set(const std::string &key, const std::string &value)
  {
    members.emplace_back(key, quoted(value));
    object_index.push_back(-1);
    return *this;
  }

  JsonObject &
  JsonObject::set(const std::string &key, const char *value)
  {
    return set(key, std::string(value));
  }

  JsonObject &
  JsonObject::set(const std::string &key, const std::vector<double> &values)
  {
    std::string text = "[";
    for (unsigned int i = 0; i < values.size(); ++i)
      text += (i > 0 ? ", " : "") + number(values[i]);
    members.emplace_back(key, text + "]");
    object_index.push_back(-1);
    return *this;
  }

  JsonObject &
  JsonObject::set(const std::string &key, const JsonObject &object)
  {
    members.emplace_back(key, "");
    object_index.push_back(objects.size());
    objects.emplace_back(key, object);
    return *this;
  }

  JsonObject &
  JsonObject::append(const JsonObject &other)
  {
    for (unsigned int i = 0; i < other.members.size(); ++i)
      if (other.object_index[i] < 0)
        {
          members.push_back(other.members[i]);
          object_index.push_back(-1);
        }
      else
        set(other.members[i].first, other.objects[other.object_index[i]].second);
    return *this;
  }

  std::string
  JsonObject::str(const unsigned int indent, const unsigned int level) const
  {
    const std::string pad(indent * (level + 1), ' ');
    std::string       out = "{\n";
    for (unsigned int i = 0; i < members.size(); ++i)
      {
        out += pad + quoted(members[i].first) + ": ";
        out += object_index[i] < 0 ? members[i].second :
                                     objects[object_index[i]].second.str(indent, level + 1);
        out += (i + 1 < members.size() ? ",\n" : "\n");
      }
    return out + std::string(indent * level, ' ') + "}";
  }
} // namespace FetiContact
