#pragma once

#include <ostream>
#include <streambuf>
#include <vector>

namespace FetiContact
{
  /** An output stream that writes to several streams at once (screen and log.txt). */
  class TeeStream : public std::ostream
  {
  public:
    TeeStream()
      : std::ostream(&buffer)
    {}
    /** Adds a destination. */
    void
    add(std::ostream &out)
    {
      buffer.targets.push_back(out.rdbuf());
    }

  private:
    struct Buffer : public std::streambuf
    {
      std::vector<std::streambuf *> targets;
      int
      overflow(int c) override
      {
        if (c != EOF)
          for (auto *t : targets)
            t->sputc(static_cast<char>(c));
        return c;
      }
      std::streamsize
      xsputn(const char *s, std::streamsize n) override
      {
        for (auto *t : targets)
          t->sputn(s, n);
        return n;
      }
      int
      sync() override
      {
        for (auto *t : targets)
          t->pubsync();
        return 0;
      }
    };
    Buffer buffer;
  };
} // namespace FetiContact
