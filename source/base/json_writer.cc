#include <feticontact/base/json_writer.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

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

    /**
     * The length of the well-formed UTF-8 sequence at @p s[i] (RFC 3629: no overlong forms, no
     * surrogates, at most U+10FFFF), or 0 if the bytes there are not one.
     */
    std::size_t
    utf8_sequence_length(const std::string &s, const std::size_t i)
    {
      const auto byte = [&](const std::size_t k) {
        return k < s.size() ? static_cast<unsigned char>(s[k]) : 0u;
      };
      const unsigned int b0   = byte(i);
      const auto continuation = [&](const std::size_t k) { return (byte(k) & 0xC0) == 0x80; };
      if (b0 < 0x80)
        return 1;
      if (b0 >= 0xC2 && b0 <= 0xDF)
        return continuation(i + 1) ? 2 : 0;
      if (b0 >= 0xE0 && b0 <= 0xEF)
        {
          const unsigned int b1 = byte(i + 1);
          if ((b0 == 0xE0 && b1 < 0xA0) || (b0 == 0xED && b1 > 0x9F))
            return 0;
          return continuation(i + 1) && continuation(i + 2) ? 3 : 0;
        }
      if (b0 >= 0xF0 && b0 <= 0xF4)
        {
          const unsigned int b1 = byte(i + 1);
          if ((b0 == 0xF0 && b1 < 0x90) || (b0 == 0xF4 && b1 > 0x8F))
            return 0;
          return continuation(i + 1) && continuation(i + 2) && continuation(i + 3) ? 4 : 0;
        }
      return 0;
    }

    /** @p s as a JSON string; bytes that are not UTF-8 become U+FFFD. */
    std::string
    quoted(const std::string &s)
    {
      std::string out = "\"";
      for (std::size_t i = 0; i < s.size();)
        {
          const char        c      = s[i];
          const std::size_t length = utf8_sequence_length(s, i);
          if (length == 0)
            {
              out += "\\ufffd";
              ++i;
              continue;
            }
          if (length > 1)
            out.append(s, i, length);
          else if (c == '"' || c == '\\')
            {
              out += '\\';
              out += c;
            }
          else if (c == '\n')
            out += "\\n";
          else if (c == '\t')
            out += "\\t";
          else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F)
            {
              char code[8];
              std::snprintf(code, sizeof(code), "\\u%04x", static_cast<unsigned int>(c));
              out += code;
            }
          else
            out += c;
          i += length;
        }
      return out + "\"";
    }
  } // namespace

  JsonObject &
  JsonObject::set(const std::string &key, const double value)
  {
    add_key(key);
    members.emplace_back(key, number(value));
    object_index.push_back(-1);
    return *this;
  }

  JsonObject &
  JsonObject::set(const std::string &key, const int value)
  {
    add_key(key);
    members.emplace_back(key, std::to_string(value));
    object_index.push_back(-1);
    return *this;
  }

  JsonObject &
  JsonObject::set(const std::string &key, const unsigned int value)
  {
    add_key(key);
    members.emplace_back(key, std::to_string(value));
    object_index.push_back(-1);
    return *this;
  }

  JsonObject &
  JsonObject::set(const std::string &key, const bool value)
  {
    add_key(key);
    members.emplace_back(key, value ? "true" : "false");
    object_index.push_back(-1);
    return *this;
  }

  JsonObject &
  JsonObject::set(const std::string &key, const std::string &value)
  {
    add_key(key);
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
    add_key(key);
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
    add_key(key);
    members.emplace_back(key, "");
    object_index.push_back(objects.size());
    objects.emplace_back(key, object);
    return *this;
  }

  void
  JsonObject::add_key(const std::string &key)
  {
    for (const auto &m : members)
      if (m.first == key)
        throw std::logic_error("JsonObject: the key <" + key + "> is set twice.");
  }

  JsonObject &
  JsonObject::set(const std::string &key, const std::vector<JsonObject> &objects)
  {
    add_key(key);
    members.emplace_back(key, "");
    object_index.push_back(-2 - static_cast<int>(arrays.size()));
    arrays.push_back(objects);
    return *this;
  }

  JsonObject &
  JsonObject::append(const JsonObject &other)
  {
    for (unsigned int i = 0; i < other.members.size(); ++i)
      if (other.object_index[i] < 0)
        {
          add_key(other.members[i].first);
          members.push_back(other.members[i]);
          object_index.push_back(-1);
        }
      else if (other.object_index[i] >= 0)
        set(other.members[i].first, other.objects[other.object_index[i]].second);
      else
        set(other.members[i].first, other.arrays[-2 - other.object_index[i]]);
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
        if (object_index[i] == -1)
          out += members[i].second;
        else if (object_index[i] >= 0)
          out += objects[object_index[i]].second.str(indent, level + 1);
        else
          {
            const auto       &array = arrays[-2 - object_index[i]];
            const std::string inner(indent * (level + 2), ' ');
            out += array.empty() ? "[" : "[\n";
            for (unsigned int k = 0; k < array.size(); ++k)
              out +=
                inner + array[k].str(indent, level + 2) + (k + 1 < array.size() ? ",\n" : "\n");
            out += (array.empty() ? "" : pad) + "]";
          }
        out += (i + 1 < members.size() ? ",\n" : "\n");
      }
    return out + std::string(indent * level, ' ') + "}";
  }
} // namespace FetiContact
