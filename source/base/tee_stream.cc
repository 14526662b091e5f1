#include <feticontact/base/tee_stream.h>

#include <cerrno>

namespace FetiContact
{
  std::streamsize
  TeeStream::Buffer::xsputn(const char *s, std::streamsize n)
  {
    for (auto &t : targets)
      if (t.out != nullptr)
        {
          errno = 0;
          t.out->write(s, n);
          check(t, errno);
        }
    return n;
  }

  int
  TeeStream::Buffer::sync()
  {
    for (auto &t : targets)
      if (t.out != nullptr)
        {
          errno = 0;
          t.out->flush();
          check(t, errno);
        }
    return 0;
  }
} // namespace FetiContact
