#pragma once

#include <string>

namespace FetiContact
{
  /**
   * A run's claim on its output directory: the file `feticontact.lock` in it, holding the
   * process id and host name of the run and locked (flock) while the run lasts; the destructor
   * removes it. A directory whose lock a running process holds is refused, so that two runs never
   * mix their files in one folder. A lock file left by a run that ended without removing it
   * (killed) is not locked by anybody: it is taken over, and note() says whose it was.
   */
  class OutputLock
  {
  public:
    /** The name of the lock file in the output directory. */
    static inline const std::string file_name = "feticontact.lock";

    OutputLock() = default;
    ~OutputLock();
    OutputLock(const OutputLock &) = delete;
    OutputLock &
    operator=(const OutputLock &) = delete;

    /**
     * Creates @p directory if needed and takes its lock. Throws OutputError if another process
     * holds it (naming the process and host from the file) or if the lock file cannot be
     * created.
     */
    void
    acquire(const std::string &directory);

    /** Releases the lock and removes the lock file (also done by the destructor). */
    void
    release();

    /** "" or, if a stale lock was taken over, a sentence saying whose it was. */
    const std::string &
    note() const
    {
      return stale_note;
    }

  private:
    int         descriptor = -1;
    std::string path;
    std::string stale_note;
  };
} // namespace FetiContact
