#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <feticontact/base/mpi_tools.h>
#include <feticontact/base/output_files.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <regex>
#include <system_error>
#include <unistd.h>

namespace FetiContact
{
  namespace
  {
    /**
     * The system's reason for a failed write of @p path: @p error if set, else a full device if
     * the device has (nearly) no space left, else a generic one.
     */
    std::string
    system_reason(const int error, const std::string &path = "")
    {
      if (error != 0)
        return std::strerror(error);
      std::error_code ignored;
      const auto      folder = std::filesystem::path(path).parent_path();
      if (!path.empty() &&
          std::filesystem::space(folder.empty() ? "." : folder, ignored).available < 65536 &&
          !ignored)
        return std::strerror(ENOSPC);
      return "the write did not complete";
    }
  } // namespace

  ResultFiles::~ResultFiles()
  {
    for (auto &f : files)
      if (!f.renamed)
        {
          if (f.out)
            f.out->close();
          std::error_code ignored;
          std::filesystem::remove(f.path + OutputFiles::partial_suffix, ignored);
        }
  }

  std::ostream &
  ResultFiles::open(const std::string &path)
  {
    File file{path, std::make_unique<std::ofstream>()};
    errno = 0;
    file.out->open(path + OutputFiles::partial_suffix);
    const int error = errno;
    files.push_back(std::move(file));
    if (!*files.back().out)
      throw OutputError("Cannot create the output file <" + path + ">: " + system_reason(error) +
                        ".");
    return *files.back().out;
  }

  void
  ResultFiles::write(const std::string &path, const std::function<void(std::ostream &)> &writer)
  {
    std::ostream &out = open(path);
    try
      {
        writer(out);
      }
    catch (const dealii::ExceptionBase &)
      {
        complete(); // names the first file whose write failed
        throw OutputError("Cannot write the output file <" + path + ">: " + system_reason(0, path) +
                          ".");
      }
  }

  std::string
  ResultFiles::reserve(const std::string &path)
  {
    files.push_back(File{path, nullptr});
    return path + OutputFiles::partial_suffix;
  }

  void
  ResultFiles::write_collectively(const MPI_Comm     comm,
                                  const std::string &path,
                                  const std::string &local_text)
  {
    const std::string partial = path + OutputFiles::partial_suffix;
    const bool        root    = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
    const auto        failure = [&](const int error) {
      return "Cannot write the output file <" + path + ">: " + system_reason(error, path) + ".";
    };
    // Rank 0 creates the file (empty) before any rank opens it, with the permissions of the
    // other result files (0666 less the umask).
    std::string error;
    if (root)
      {
        files.push_back(File{path, nullptr});
        errno                = 0;
        const int descriptor = ::open(partial.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
        if (descriptor < 0 || ::close(descriptor) != 0)
          error = "Cannot create the output file <" + path + ">: " + system_reason(errno) + ".";
      }
    OutputFiles::throw_if_any_failed(comm, error);

    unsigned long long length = local_text.size(), offset = 0;
    MPI_Exscan(&length, &offset, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
    if (root)
      offset = 0; // MPI_Exscan leaves rank 0's result undefined
    if (length > 0)
      {
        errno                = 0;
        const int descriptor = ::open(partial.c_str(), O_WRONLY);
        if (descriptor < 0)
          error = failure(errno);
        for (std::size_t done = 0; error.empty() && done < length;)
          {
            errno             = 0;
            const ssize_t put = ::pwrite(descriptor,
                                         local_text.data() + done,
                                         length - done,
                                         static_cast<off_t>(offset + done));
            if (put <= 0 && errno != EINTR)
              error = failure(put < 0 ? errno : 0);
            else if (put > 0)
              done += put;
          }
        errno = 0;
        if (descriptor >= 0 && ::close(descriptor) != 0 && error.empty())
          error = failure(errno);
      }
    OutputFiles::throw_if_any_failed(comm, error);
  }

  void
  ResultFiles::complete()
  {
    for (auto &f : files)
      if (f.out && !f.closed)
        {
          errno = 0;
          f.out->flush();
          int        error   = errno;
          const bool written = static_cast<bool>(*f.out);
          errno              = 0;
          f.out->close();
          if (error == 0)
            error = errno;
          f.closed = true;
          if (!written || f.out->fail())
            throw OutputError("Cannot write the output file <" + f.path +
                              ">: " + system_reason(error, f.path) + ".");
        }
  }

  void
  ResultFiles::commit()
  {
    complete();
    try
      {
        for (auto &f : files)
          if (!f.renamed)
            {
              OutputFiles::rename(f.path + OutputFiles::partial_suffix, f.path);
              f.renamed = true;
            }
      }
    catch (const OutputError &)
      {
        remove_all();
        throw;
      }
  }

  void
  ResultFiles::remove_all()
  {
    for (auto &f : files)
      {
        if (f.out && !f.closed)
          f.out->close();
        f.closed = true;
        std::error_code ignored;
        std::filesystem::remove(f.renamed ? f.path : f.path + OutputFiles::partial_suffix, ignored);
        f.renamed = true; // nothing left for the destructor
      }
  }

  namespace OutputFiles
  {
    bool
    written_by_this_program(const std::string &name)
    {
      static const std::regex names(
        "(log\\.txt|summary\\.json|parameters\\.prm|input\\.prm|history\\.csv|contact\\.csv|"
        "displacements\\.csv|solution\\.pvd|solution\\.pvtu|solution_[0-9]+\\.vtu|"
        "contact_surface\\.pvtu|contact_surface(_[0-9]+)?\\.vtu|contact_surface\\.pvd|"
        "fclib_problem\\.hdf5|"
        "convergence_table\\.txt|convergence_table\\.org|refinement_study\\.json)"
        "(\\.partial)?");
      return std::regex_match(name, names);
    }

    void
    clean(const std::string &directory, const std::string &input)
    {
      namespace fs = std::filesystem;
      std::error_code error;
      const auto      same_as_input = [&](const fs::path &path) {
        std::error_code ignored;
        return !input.empty() && fs::equivalent(path, input, ignored);
      };
      fs::create_directories(directory, error);
      if (error || !fs::is_directory(directory))
        throw OutputError("Output/Directory: cannot create the output directory <" + directory +
                          ">: " + (error ? error.message() : "a file of that name exists") + ".");
      static const std::regex cycle("cycle-[0-9]+");
      for (const auto &entry : fs::directory_iterator(directory))
        {
          const std::string name = entry.path().filename().string();
          if (entry.is_directory() && std::regex_match(name, cycle))
            {
              clean(entry.path().string(), input);
              if (fs::is_empty(entry.path()))
                fs::remove(entry.path(), error);
            }
          else if (entry.is_directory() && written_by_this_program(name))
            throw OutputError("Output/Directory: <" + entry.path().string() +
                              "> is a folder where this program writes a result file; remove "
                              "or rename it.");
          else if (!entry.is_directory() && written_by_this_program(name) &&
                   !same_as_input(entry.path()))
            if (!fs::remove(entry.path(), error) || error)
              throw OutputError("Output/Directory: cannot remove the earlier result <" +
                                entry.path().string() + ">: " + error.message() + ".");
        }
      // A probe: the directory must take new files (a read-only mount, a full device).
      const std::string probe = directory + "/log.txt" + partial_suffix;
      errno                   = 0;
      std::FILE *file         = std::fopen(probe.c_str(), "w");
      const int  open_error   = errno;
      if (file == nullptr)
        throw OutputError("Output/Directory: cannot write into the output directory <" + directory +
                          ">: " + system_reason(open_error) + ".");
      std::fclose(file);
      fs::remove(probe, error);
    }

    std::string
    failure_reason(const int error, const std::string &path)
    {
      return system_reason(error, path);
    }

    void
    rename(const std::string &from, const std::string &to)
    {
      std::error_code error;
      std::filesystem::rename(from, to, error);
      if (error)
        throw OutputError("Cannot rename the output file <" + from + "> to <" + to +
                          ">: " + error.message() + ".");
    }

    void
    throw_if_any_failed(const MPI_Comm comm, const std::string &local_error)
    {
      const std::string error = MPITools::first_error(comm, local_error);
      if (!error.empty())
        throw OutputError(error);
    }
  } // namespace OutputFiles
} // namespace FetiContact
