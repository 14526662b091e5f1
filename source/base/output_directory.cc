#include <feticontact/base/mpi_tools.h>
#include <feticontact/base/output_directory.h>

#include <cerrno>
#include <cstring>

namespace FetiContact
{
  OutputDirectory::OutputDirectory(const MPI_Comm comm, const std::string &path)
    : comm(comm)
    , rank(dealii::Utilities::MPI::this_mpi_process(comm))
    , directory(path)
  {}

  void
  OutputDirectory::prepare(const std::string &effective_parameters, const std::string &input)
  {
    on_all_ranks([&]() {
      if (rank != 0)
        return;
      // Files of an earlier run must not pass for this run's.
      OutputFiles::clean(directory);
      // The input as read, at once: they are no results, and a run that stops keeps them.
      ResultFiles inputs;
      inputs.open(directory + "/parameters.prm") << effective_parameters;
      inputs.open(directory + "/input.prm") << input;
      inputs.commit();
      errno = 0;
      log_file.open(directory + "/log.txt");
      if (!log_file)
        throw OutputError("Cannot create the output file <" + directory +
                          "/log.txt>: " + std::strerror(errno) + ".");
      tee.add(log_file, directory + "/log.txt");
    });
  }

  void
  OutputDirectory::on_all_ranks(const std::function<void()> &write) const
  {
    MPITools::collectively<OutputError>(comm, write);
  }

  void
  OutputDirectory::check_log()
  {
    tee.flush();
    on_all_ranks([this]() {
      if (!tee.failed().empty())
        throw OutputError("Cannot write the output file <" + tee.failed() + ">: " +
                          OutputFiles::failure_reason(tee.failure_errno(), tee.failed()) + ".");
    });
  }

  void
  OutputDirectory::write_summary(const std::string &text)
  {
    on_all_ranks([&]() {
      if (rank == 0)
        summary_file.open(directory + "/summary.json") << text << '\n';
    });
  }

  void
  OutputDirectory::commit()
  {
    on_all_ranks([this]() {
      result_files.complete();
      summary_file.complete();
    });
    check_log();
    try
      {
        on_all_ranks([this]() { result_files.commit(); });
      }
    catch (const OutputError &)
      {
        // Also the ranks whose files were renamed: no set of result files stays incomplete.
        result_files.remove_all();
        throw;
      }
    on_all_ranks([this]() { summary_file.commit(); });
  }
} // namespace FetiContact
