#pragma once

#include <map>
#include <memory>
#include <mpi.h>
#include <set>
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
   * A file that cannot be read twice (a pipe, `/dev/stdin`) is read once (share_unrepeatable())
   * and its text kept for every later reading; its relative paths are taken from the working
   * directory.
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

    /**
     * Every subsection path that @p text opens (names joined by '/', e.g. "Contact/Zone 1"),
     * with the paths of the subsections around it.
     */
    static std::set<std::string>
    subsections(const std::string &text);

    /**
     * The text of @p filename: for a regular file its bytes; for anything else (a pipe, a FIFO,
     * `/dev/stdin` of a pipe) the bytes read once by share_unrepeatable(), or read now and kept.
     * Throws InputError if it cannot be opened.
     */
    static std::string
    bytes_of(const std::string &filename, const std::string &what);

    /**
     * If @p filename is not a regular file (a pipe, `/dev/stdin`), rank 0 of @p comm reads it
     * (under mpirun only rank 0 has the standard input) and sends its bytes to every rank, which
     * keeps them for bytes_of(). Collective; does nothing for a regular file.
     */
    static void
    share_unrepeatable(const MPI_Comm comm, const std::string &filename);

    /** The bytes kept of the unrepeatable file @p filename, unchecked ("" if none). */
    static std::string
    kept_text(const std::string &filename);

    /**
     * Whether @p filename is read once and kept: not a regular file (a pipe, a FIFO), or a name
     * of an open file (/dev/stdin, /dev/fd/N, /proc/…: under mpirun only rank 0 has the
     * standard input).
     */
    static bool
    is_unrepeatable(const std::string &filename);
  };

  /**
   * Where each entry of a parameter file was set: the file and line of its last `set` (or a
   * --set option), so that a file named in an entry is found next to the parameter file that
   * names it, also in an included file.
   */
  class EntryOrigins
  {
  public:
    /** No origins: relative paths are taken from the working directory. */
    EntryOrigins() = default;

    /**
     * The origins of the entries of @p text_with_overrides: the text of @p file followed by the
     * lines of the --set options (whose origin is the working directory).
     */
    EntryOrigins(const ParameterFileText &file, const std::string &text_with_overrides);

    /** The same origins with entry keys taken inside @p subsection ("Body 1"). */
    EntryOrigins
    in(const std::string &subsection) const;

    /**
     * @p value, the file name given in the entry @p key ("Mesh/File" inside "Body 1"), as a path:
     * an absolute one as it is, a relative one joined to the folder of the parameter file that set
     * it (the working directory for a --set option, a pipe or an entry never set).
     */
    std::string
    resolve(const std::string &key, const std::string &value) const;

    /** Where @p key was set, for messages: " (set in <FILE>, line N)", or "" if not in a file. */
    std::string
    where(const std::string &key) const;

  private:
    /** Per entry key: the parameter file and line of its last `set`. */
    std::shared_ptr<const std::map<std::string, std::pair<std::string, unsigned int>>> origin;
    /** The subsections that keys are taken in ("Body 1/"). */
    std::string prefix;

    /** The origin of @p key inside #prefix, or null. */
    const std::pair<std::string, unsigned int> *
    find(const std::string &key) const;
  };

  /**
   * Throws InputError if the bytes @p head (the start of the file @p file, @p what says which
   * kind of file it is) are not plain 8-bit text: a UTF-8 byte-order mark, UTF-16 (with or
   * without byte-order mark) or any other NUL byte. Also for a folder given as a file.
   */
  void
  check_text_file(const std::string &file, const std::string &what);
} // namespace FetiContact::Parameters
