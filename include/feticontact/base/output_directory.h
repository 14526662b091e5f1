#pragma once

#include <feticontact/base/output_files.h>
#include <feticontact/base/tee_stream.h>

#include <fstream>
#include <functional>
#include <mpi.h>
#include <string>

namespace FetiContact
{
  /**
   * The output directory of one run, from its preparation to the commit of its results.
   * prepare() removes every file that an earlier run wrote there (OutputFiles::clean()), writes
   * the input files parameters.prm and input.prm at once and adds log.txt to the run's log
   * (rank 0). The result files are written under temporary names (results(), write_summary());
   * commit() renames them when the run has written all of them, summary.json last. A run that
   * stops before leaves no result file: ResultFiles removes the files it did not commit, and a
   * rename that fails on one rank removes the result files of every rank.
   *
   * Every write goes through on_all_ranks(), so that an OutputError of one rank stops all ranks
   * together. The claim on the directory (OutputLock) is held by the program around all runs made
   * in it.
   */
  class OutputDirectory
  {
  public:
    /** The directory @p path of a run on the ranks of @p comm; nothing is created yet. */
    OutputDirectory(const MPI_Comm comm, const std::string &path);

    /** The run's log: the terminal and log.txt on rank 0 (once added), nothing elsewhere. */
    TeeStream &
    log()
    {
      return tee;
    }

    /**
     * Removes every file of an earlier run, writes @p effective_parameters into parameters.prm
     * and @p input into input.prm, and creates log.txt as a destination of log() (rank 0).
     * Collective; throws OutputError on every rank if a file cannot be written.
     */
    void
    prepare(const std::string &effective_parameters, const std::string &input);

    /**
     * Runs @p write (on this rank) and makes an OutputError of any rank every rank's, so that
     * all ranks stop together. Collective.
     */
    void
    on_all_ranks(const std::function<void()> &write) const;

    /** Throws OutputError on every rank if rank 0's log.txt could not be written. Collective. */
    void
    check_log();

    /** This rank's result files, renamed to their final names by commit(). */
    ResultFiles &
    results()
    {
      return result_files;
    }

    /** Writes @p text and a line end into summary.json (rank 0). Collective. */
    void
    write_summary(const std::string &text);

    /**
     * Renames every rank's result files to their final names, summary.json last; if a rename
     * fails on any rank, removes the result files of every rank and throws OutputError.
     * Collective.
     */
    void
    commit();

  private:
    MPI_Comm           comm;
    const unsigned int rank;
    const std::string  directory;
    std::ofstream      log_file;
    TeeStream          tee;
    ResultFiles        result_files;
    /** summary.json, renamed after every other result file. */
    ResultFiles summary_file;
  };
} // namespace FetiContact
