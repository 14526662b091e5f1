#include <feticontact/base/input_parsing.h>
#include <feticontact/scene/parameter_file.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

namespace FetiContact::Parameters
{
  namespace
  {
    /** Collapses runs of white space into one blank and trims, as deal.II does with names. */
    std::string
    normalized(const std::string &text)
    {
      std::string out;
      bool        blank = false;
      for (const char c : InputParsing::trim(text))
        if (c == ' ' || c == '\t')
          blank = true;
        else
          {
            if (blank)
              out += ' ';
            blank = false;
            out += c;
          }
      return out;
    }

    /** A logical line of a parameter file: comment removed, continuation lines joined. */
    struct Line
    {
      std::string  text;
      unsigned int first_line;
    };

    std::vector<Line>
    logical_lines(const std::string &text)
    {
      std::vector<Line>  lines;
      std::istringstream in(text);
      std::string        raw, pending;
      unsigned int       number = 0, first = 0;
      while (std::getline(in, raw))
        {
          ++number;
          if (pending.empty())
            first = number;
          const auto hash = raw.find('#');
          if (hash != std::string::npos)
            raw.erase(hash);
          const std::string trimmed = InputParsing::trim(raw);
          if (!trimmed.empty() && trimmed.back() == '\\')
            {
              pending += trimmed.substr(0, trimmed.size() - 1);
              continue;
            }
          lines.push_back({pending + trimmed, first});
          pending.clear();
        }
      if (!pending.empty())
        lines.push_back({pending, first});
      return lines;
    }

    /** Whether @p line starts with the keyword @p word followed by white space. */
    bool
    starts_with_keyword(const std::string &line, const std::string &word)
    {
      return line.size() > word.size() && line.compare(0, word.size(), word) == 0 &&
             (line[word.size()] == ' ' || line[word.size()] == '\t');
    }

    /** A `set` line: the entry's subsection path and name joined by '/', its value, its line. */
    struct Entry
    {
      std::string  key, value;
      unsigned int line;
    };

    /** Every `set` line of @p text with the subsections it is in; malformed lines are skipped. */
    std::vector<Entry>
    entries(const std::string &text)
    {
      std::vector<Entry>       found;
      std::vector<std::string> path;
      for (const auto &l : logical_lines(text))
        if (starts_with_keyword(l.text, "subsection"))
          path.push_back(normalized(l.text.substr(10)));
        else if (l.text == "end" && !path.empty())
          path.pop_back();
        else if (starts_with_keyword(l.text, "set"))
          {
            const auto eq = l.text.find('=');
            if (eq == std::string::npos)
              continue;
            std::string key;
            for (const auto &p : path)
              key += p + "/";
            found.push_back({key + normalized(l.text.substr(3, eq - 3)),
                             InputParsing::trim(l.text.substr(eq + 1)),
                             l.first_line});
          }
      return found;
    }

    /** The folder against which the relative paths named in @p filename are taken. */
    std::filesystem::path
    folder_of(const std::string &filename)
    {
      return ParameterFileText::is_unrepeatable(filename) ?
               std::filesystem::path() :
               std::filesystem::path(filename).parent_path();
    }

    void
    expand(const std::string &filename, std::vector<std::string> &stack, ParameterFileText &result)
    {
      std::stringstream buffer(ParameterFileText::bytes_of(filename, "parameter file"));

      std::error_code   error;
      const std::string canonical = std::filesystem::weakly_canonical(filename, error).string();
      stack.push_back(canonical);

      // Entries set twice in this file: by subsection path and name, (line, value).
      std::map<std::string, std::pair<unsigned int, std::string>> seen;
      for (const auto &e : entries(buffer.str()))
        {
          const auto [it, inserted] = seen.emplace(e.key, std::make_pair(e.line, e.value));
          if (!inserted)
            {
              result.warnings.push_back(
                "Parameter file <" + filename + ">: '" + e.key + "' is set twice, line " +
                std::to_string(it->second.first) + " <" + it->second.second + "> and line " +
                std::to_string(e.line) + " <" + e.value + ">; the last one is used.");
              it->second = {e.line, e.value};
            }
        }

      std::istringstream lines(buffer.str());
      std::string        raw;
      unsigned int       number = 0;
      while (std::getline(lines, raw))
        {
          ++number;
          const std::string trimmed = InputParsing::trim(raw);
          if (starts_with_keyword(trimmed, "include"))
            {
              std::string target = InputParsing::trim(trimmed.substr(7));
              const auto  hash   = target.find('#');
              if (hash != std::string::npos)
                target = InputParsing::trim(target.substr(0, hash));
              const auto beside = folder_of(filename) / target;
              if (std::filesystem::exists(beside))
                target = beside.string();
              const std::string target_canonical =
                std::filesystem::weakly_canonical(target, error).string();
              for (const auto &open : stack)
                if (open == target_canonical)
                  throw InputError("Parameter file <" + filename + ">, line " +
                                   std::to_string(number) + ": 'include " + target +
                                   "' names a file that is being read already (an include "
                                   "cycle).");
              require(stack.size() < 32,
                      "Parameter file <" + filename + ">: includes nested more than 32 deep.");
              expand(target, stack, result);
              continue;
            }
          result.text += raw + "\n";
          result.origin.emplace_back(filename, number);
        }
      stack.pop_back();
    }
  } // namespace

  namespace
  {
    /** The bytes of the files read once (not regular files), by the name they were given. */
    std::map<std::string, std::string> &
    kept_bytes()
    {
      static std::map<std::string, std::string> kept;
      return kept;
    }

    /** check_text_file() on the first bytes @p head of @p file. */
    void
    check_text_head(const std::string &head, const std::string &file, const std::string &what);
  } // namespace

  bool
  ParameterFileText::is_unrepeatable(const std::string &filename)
  {
    // A pipe or FIFO; or the standard input by name, which under mpirun only rank 0 has.
    const auto under = [&](const std::string &folder) {
      return filename.compare(0, folder.size(), folder) == 0;
    };
    return kept_bytes().count(filename) > 0 ||
           (std::filesystem::exists(filename) && !std::filesystem::is_regular_file(filename) &&
            !std::filesystem::is_directory(filename)) ||
           under("/dev/stdin") || under("/dev/fd/") || under("/proc/");
  }

  std::string
  ParameterFileText::bytes_of(const std::string &filename, const std::string &what)
  {
    const auto kept = kept_bytes().find(filename);
    if (kept == kept_bytes().end())
      {
        require(!std::filesystem::is_directory(filename),
                "The " + what + " <" + filename + "> is a folder, not a file.");
        std::ifstream   in(filename, std::ios::binary);
        std::error_code error;
        require(static_cast<bool>(in),
                "Cannot open the " + what + " <" + filename + "> (looked for at <" +
                  std::filesystem::absolute(filename, error).lexically_normal().string() + ">).");
        std::stringstream buffer;
        buffer << in.rdbuf();
        if (!is_unrepeatable(filename))
          {
            check_text_head(buffer.str().substr(0, 4096), filename, what);
            return buffer.str();
          }
        kept_bytes()[filename] = buffer.str();
      }
    const std::string &bytes = kept_bytes()[filename];
    check_text_head(bytes.substr(0, 4096), filename, what);
    return bytes;
  }

  std::string
  ParameterFileText::kept_text(const std::string &filename)
  {
    const auto kept = kept_bytes().find(filename);
    return kept == kept_bytes().end() ? "" : kept->second;
  }

  void
  ParameterFileText::share_unrepeatable(const MPI_Comm comm, const std::string &filename)
  {
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    // The decision is rank 0's: under mpirun the others' standard input is /dev/null.
    int unrepeatable = rank == 0 && is_unrepeatable(filename);
    MPI_Bcast(&unrepeatable, 1, MPI_INT, 0, comm);
    if (!unrepeatable)
      return;
    std::string bytes;
    if (rank == 0)
      {
        std::ifstream     in(filename, std::ios::binary);
        std::stringstream buffer;
        buffer << in.rdbuf();
        bytes = buffer.str();
      }
    unsigned long long size = bytes.size();
    MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, 0, comm);
    bytes.resize(size);
    MPI_Bcast(bytes.data(), int(size), MPI_CHAR, 0, comm);
    kept_bytes()[filename] = bytes;
  }

  void
  check_text_file(const std::string &file, const std::string &what)
  {
    require(!std::filesystem::is_directory(file),
            "The " + what + " <" + file + "> is a folder, not a file.");
    std::ifstream in(file, std::ios::binary);
    if (!in)
      return; // the caller names a missing file
    std::string head(4096, '\0');
    in.read(head.data(), head.size());
    head.resize(in.gcount());
    check_text_head(head, file, what);
  }

  namespace
  {
    void
    check_text_head(const std::string &head, const std::string &file, const std::string &what)
    {
      const auto starts = [&](const std::string &bytes) {
        return head.compare(0, bytes.size(), bytes) == 0;
      };
      require(!starts("\xEF\xBB\xBF"),
              "The " + what + " <" + file +
                "> starts with a UTF-8 byte-order mark: save it as plain UTF-8 or ASCII text "
                "without one.");
      require(!starts("\xFF\xFE") && !starts("\xFE\xFF"),
              "The " + what + " <" + file +
                "> is UTF-16 text (it starts with a UTF-16 byte-order mark): save it as UTF-8 or "
                "ASCII text.");
      const auto nul = head.find('\0');
      require(nul == std::string::npos,
              "The " + what + " <" + file + "> contains a NUL byte at offset " +
                std::to_string(nul) +
                ": it is not 8-bit text (UTF-16 without a byte-order mark, or a binary file).");
    }
  } // namespace

  ParameterFileText
  ParameterFileText::read(const std::string &filename)
  {
    ParameterFileText        result;
    std::vector<std::string> stack;
    expand(filename, stack, result);
    return result;
  }

  std::string
  ParameterFileText::last_value(const std::string &text,
                                const std::string &subsection_path,
                                const std::string &entry,
                                const std::string &fallback)
  {
    std::string value = fallback;
    for (const auto &e : entries(text))
      if (e.key == subsection_path + "/" + entry)
        value = e.value;
    return value;
  }

  std::set<std::string>
  ParameterFileText::subsections(const std::string &text)
  {
    std::set<std::string>    found;
    std::vector<std::string> path;
    for (const auto &l : logical_lines(text))
      if (starts_with_keyword(l.text, "subsection"))
        {
          path.push_back(normalized(l.text.substr(10)));
          std::string joined;
          for (const auto &p : path)
            joined += (joined.empty() ? "" : "/") + p;
          found.insert(joined);
        }
      else if (l.text == "end" && !path.empty())
        path.pop_back();
    return found;
  }

  EntryOrigins::EntryOrigins(const ParameterFileText &file, const std::string &text_with_overrides)
  {
    auto map = std::make_shared<std::map<std::string, std::pair<std::string, unsigned int>>>();
    for (const auto &e : entries(text_with_overrides))
      if (e.line >= 1 && e.line <= file.origin.size())
        (*map)[e.key] = file.origin[e.line - 1];
      else
        map->erase(e.key); // a --set option: the working directory
    origin = map;
  }

  EntryOrigins
  EntryOrigins::in(const std::string &subsection) const
  {
    EntryOrigins scoped = *this;
    scoped.prefix += subsection + "/";
    return scoped;
  }

  const std::pair<std::string, unsigned int> *
  EntryOrigins::find(const std::string &key) const
  {
    if (!origin)
      return nullptr;
    const auto it = origin->find(prefix + key);
    return it == origin->end() ? nullptr : &it->second;
  }

  std::string
  EntryOrigins::resolve(const std::string &key, const std::string &value) const
  {
    const std::filesystem::path path(value);
    const auto                 *set_in = find(key);
    if (path.is_absolute() || path.empty() || set_in == nullptr)
      return value;
    return (folder_of(set_in->first) / path).string();
  }

  std::string
  EntryOrigins::where(const std::string &key) const
  {
    const auto *set_in = find(key);
    if (set_in == nullptr)
      return "";
    return " (set in <" + set_in->first + ">, line " + std::to_string(set_in->second) + ")";
  }
} // namespace FetiContact::Parameters
