#pragma once

#include <feticontact/base/input_parsing.h>

#include <fstream>
#include <functional>
#include <memory>
#include <mpi.h>
#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * A file of the output directory that could not be created or written (permission, a full
   * device, a path through a regular file, …). The message names the file and the system's
   * reason. It is reported like bad input: exit status 1, no file that looks like a result.
   */
  class OutputError : public InputError
  {
  public:
    using InputError::InputError;
  };

  /**
   * The result files of a run on this rank. Each is written under a temporary name
   * (`NAME.partial`); complete() flushes and closes them and checks every stream's state, and
   * commit() renames them to their final names in the order they were opened. Files not
   * committed (the run stopped, a write failed) are removed by the destructor, so that a run that
   * stops anywhere leaves no file that looks complete.
   */
  class ResultFiles
  {
  public:
    ResultFiles() = default;
    ~ResultFiles();
    ResultFiles(const ResultFiles &) = delete;
    ResultFiles &
    operator=(const ResultFiles &) = delete;

    /** Creates `@p path.partial` and returns its stream; throws OutputError if it cannot. */
    std::ostream &
    open(const std::string &path);

    /**
     * Opens @p path and runs @p writer on its stream; a library's exception about the stream
     * (deal.II's ExcIO when a write failed) becomes an OutputError naming the file and the reason.
     */
    void
    write(const std::string &path, const std::function<void(std::ostream &)> &writer);

    /**
     * For a file written by a library from its name (HDF5): registers @p path and returns the
     * temporary name to write to.
     */
    std::string
    reserve(const std::string &path);

    /**
     * Writes the @p local_text of every rank of @p comm into the one file @p path, in rank order:
     * each rank writes its own text at the offset of the texts of the ranks before it (an exclusive
     * prefix sum of the lengths), so that no rank holds more than its share. Rank 0 creates the
     * file and registers it with its set (renamed by its commit(), removed if the run stops).
     * Collective; if any rank fails, every rank throws OutputError with the first failed rank's
     * message.
     */
    void
    write_collectively(const MPI_Comm comm, const std::string &path, const std::string &local_text);

    /** Flushes, closes and checks every open file; throws OutputError naming the first failed. */
    void
    complete();

    /**
     * complete(), then renames every file to its final name; if a rename fails, removes every
     * file of this set (renamed or not) and throws OutputError naming the file and the reason.
     */
    void
    commit();

    /** Removes every file of this set, renamed or not (a commit failed on another rank). */
    void
    remove_all();

  private:
    struct File
    {
      std::string                    path;
      std::unique_ptr<std::ofstream> out; ///< null for a reserved file
      bool                           closed = false, renamed = false;
    };
    std::vector<File> files;
  };

  /** Names of the output directory's files and the operations on them. */
  namespace OutputFiles
  {
    /** The suffix of a result file while it is written. */
    inline const std::string partial_suffix = ".partial";

    /**
     * Whether @p name (a file name without directory) is one that this program writes into an
     * output directory: log.txt, summary.json, parameters.prm, input.prm, history.csv,
     * contact.csv, displacements.csv, solution.pvd, solution.pvtu, solution_NNNN.vtu,
     * contact_surface.pvd, contact_surface.pvtu, contact_surface_NNNN.vtu, fclib_problem.hdf5, the
     * refinement study's convergence_table.txt, convergence_table.org and refinement_study.json,
     * and any of these with the suffix `.partial`; also contact_surface.vtu, which folders written
     * by older versions of the program hold.
     */
    bool
    written_by_this_program(const std::string &name);

    /**
     * Creates @p directory if needed and removes from it every file this program writes
     * (written_by_this_program()) and every refinement-study folder `cycle-N` (cleaned the same
     * way, and removed when nothing else is left in it). Files of other programs stay, and so
     * does @p input (the parameter file of the run, which may be an earlier run's input.prm or
     * parameters.prm). Throws OutputError if the directory cannot be created or written into, or
     * holds a folder with the name of a result file.
     */
    void
    clean(const std::string &directory, const std::string &input = "");

    /**
     * The system's reason why writing @p path failed: the text of @p error (an errno value) if
     * non-zero, else "No space left on device" if the device has less than 64 KiB free, else a
     * generic text.
     */
    std::string
    failure_reason(const int error, const std::string &path);

    /**
     * Renames @p from to @p to (a file written under a temporary name); throws OutputError
     * naming both and the system's reason.
     */
    void
    rename(const std::string &from, const std::string &to);

    /**
     * Makes a failure of one rank everyone's: @p local_error is this rank's message (empty if
     * it succeeded). If any rank failed, every rank throws OutputError with the message of the
     * lowest failing rank. Collective.
     */
    void
    throw_if_any_failed(const MPI_Comm comm, const std::string &local_error);
  } // namespace OutputFiles
} // namespace FetiContact
