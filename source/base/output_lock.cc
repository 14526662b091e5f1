#include <feticontact/base/output_files.h>
#include <feticontact/base/output_lock.h>

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace FetiContact
{
  namespace
  {
    /** The text of the open file @p descriptor from its start (a lock file: one short line). */
    std::string
    read_all(const int descriptor)
    {
      std::string text;
      char        buffer[256];
      ::lseek(descriptor, 0, SEEK_SET);
      for (ssize_t n; (n = ::read(descriptor, buffer, sizeof buffer)) > 0;)
        text.append(buffer, n);
      while (!text.empty() && (text.back() == '\n' || text.back() == '\r'))
        text.pop_back();
      return text;
    }

    /** Whether @p descriptor is still the file named @p path (not unlinked and replaced). */
    bool
    names_the_same_file(const int descriptor, const std::string &path)
    {
      struct stat open_file, named;
      return ::fstat(descriptor, &open_file) == 0 && ::stat(path.c_str(), &named) == 0 &&
             open_file.st_dev == named.st_dev && open_file.st_ino == named.st_ino;
    }

    /** "process N on host H" from a lock file's text "N H". */
    std::string
    holder(const std::string &text)
    {
      const auto blank = text.find(' ');
      if (text.empty())
        return "an unknown process";
      if (blank == std::string::npos)
        return "process " + text;
      return "process " + text.substr(0, blank) + " on host " + text.substr(blank + 1);
    }
  } // namespace

  OutputLock::~OutputLock()
  {
    release();
  }

  void
  OutputLock::acquire(const std::string &directory)
  {
    std::error_code error;
    std::filesystem::create_directories(directory, error);
    if (error || !std::filesystem::is_directory(directory))
      throw OutputError("Output/Directory: cannot create the output directory <" + directory +
                        ">: " + (error ? error.message() : "a file of that name exists") + ".");
    path = directory + "/" + file_name;
    // The holder may remove the file between our open and our lock: then lock the new one.
    for (unsigned int attempt = 0; attempt < 100; ++attempt)
      {
        descriptor = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (descriptor < 0)
          throw OutputError("Output/Directory: cannot create the lock file <" + path +
                            ">: " + std::strerror(errno) + ".");
        if (::flock(descriptor, LOCK_EX | LOCK_NB) != 0)
          {
            const int         cause = errno;
            const std::string text  = read_all(descriptor);
            ::close(descriptor);
            descriptor = -1;
            if (cause == EWOULDBLOCK)
              throw OutputError("Output/Directory: <" + directory + "> is in use by another run (" +
                                holder(text) + ", lock file <" + path +
                                ">); wait until it ends or choose another Output/Directory.");
            throw OutputError("Output/Directory: cannot lock <" + path +
                              ">: " + std::strerror(cause) + ".");
          }
        if (names_the_same_file(descriptor, path))
          break;
        ::close(descriptor);
        descriptor = -1;
      }
    if (descriptor < 0)
      throw OutputError("Output/Directory: cannot lock <" + path +
                        ">: its lock file is removed and created again by other runs.");
    const std::string earlier = read_all(descriptor);
    if (!earlier.empty())
      stale_note = "took over the lock file <" + path + "> of " + holder(earlier) +
                   ", which ended without removing it (killed?); its files in <" + directory +
                   "> are removed.";
    char host[256] = "";
    ::gethostname(host, sizeof host - 1);
    const std::string text = std::to_string(::getpid()) + " " + host + "\n";
    if (::ftruncate(descriptor, 0) != 0 || ::lseek(descriptor, 0, SEEK_SET) != 0 ||
        ::write(descriptor, text.data(), text.size()) != ssize_t(text.size()))
      {
        const int cause = errno;
        release();
        throw OutputError("Output/Directory: cannot write the lock file <" + path +
                          ">: " + std::strerror(cause) + ".");
      }
  }

  void
  OutputLock::release()
  {
    if (descriptor < 0)
      return;
    // Removed while still locked: a run waiting for the lock then finds the file gone and
    // creates a new one.
    ::unlink(path.c_str());
    ::close(descriptor);
    descriptor = -1;
  }
} // namespace FetiContact
