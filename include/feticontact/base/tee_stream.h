#pragma once

#include <ostream>
#include <streambuf>
#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * An output stream that writes to several streams at once (screen and log.txt). A destination
   * whose write fails (a full device) is dropped at once, so that nothing more is written into
   * its failed buffer, and failed() tells which one failed.
   */
  class TeeStream : public std::ostream
  {
  public:
    TeeStream()
      : std::ostream(&buffer)
    {}
    /** Adds a destination; @p name is how failed() names it. */
    void
    add(std::ostream &out, const std::string &name = "")
    {
      buffer.targets.push_back({&out, name});
    }

    /** The name of the first destination whose write failed, or an empty string. */
    const std::string &
    failed() const
    {
      return buffer.failed;
    }

    /** The system's error number at the first failed write (0: none recorded). */
    int
    failure_errno() const
    {
      return buffer.failed_errno;
    }

  private:
    struct Target
    {
      std::ostream *out;
      std::string   name;
    };

    struct Buffer : public std::streambuf
    {
      std::vector<Target> targets;
      std::string         failed;
      int                 failed_errno = 0;

      void
      check(Target &t, const int error)
      {
        if (t.out != nullptr && !*t.out)
          {
            if (failed.empty())
              {
                failed       = t.name.empty() ? std::string("an output stream") : t.name;
                failed_errno = error;
              }
            t.out = nullptr;
          }
      }

      int
      overflow(int c) override
      {
        if (c != EOF)
          {
            const char ch = static_cast<char>(c);
            xsputn(&ch, 1);
          }
        return c;
      }

      std::streamsize
      xsputn(const char *s, std::streamsize n) override;

      int
      sync() override;
    };
    Buffer buffer;
  };
} // namespace FetiContact
