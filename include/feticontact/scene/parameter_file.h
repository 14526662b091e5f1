#pragma once

#include <string>
#include <utility>
#include <vector>

namespace FetiContact::Parameters
{
  /**
   * The text of a parameter file as deal.II's ParameterHandler parses it: the file with every
   * `include` line replaced by the text of the file it names (resolved against the including
   * file's folder, then the working directory), the origin of every line, and warnings about
   * entries set twice in one subsection of one file. Checked on reading: the file exists, is no
   * folder, is text (no UTF-16, byte-order mark or NUL byte), and includes no file that is being
   * read already (an include cycle). Failures throw InputError naming the file and the cause.
   */
  struct ParameterFileText
  {
    /** The expanded text, one line per line of the files it came from. */
    std::string text;
    /** Per line of #text: file name and line number (from 1). */
    std::vector<std::pair<std::string, unsigned int>> origin;
    /** "entry set twice" warnings, one per repeated entry. */
    std::vector<std::string> warnings;

    /** Reads @p filename and the files it includes. */
    static ParameterFileText
    read(const std::string &filename);

    /**
     * The value the last `set` of @p entry in subsection @p subsection_path (names joined by '/')
     * gives in @p text, or @p fallback if none; a lenient scan that needs no declaration and
     * ignores malformed lines (to find Output/Directory in a file that fails to parse).
     */
    static std::string
    last_value(const std::string &text,
               const std::string &subsection_path,
               const std::string &entry,
               const std::string &fallback);
  };

  /**
   * Throws InputError if the bytes @p head (the start of the file @p file, @p what says which
   * kind of file it is) are not plain 8-bit text: a UTF-8 byte-order mark, UTF-16 (with or
   * without byte-order mark) or any other NUL byte. Also for a folder given as a file.
   */
  void
  check_text_file(const std::string &file, const std::string &what);
} // namespace FetiContact::Parameters
