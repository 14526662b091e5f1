#include <feticontact/base/tee_stream.h>

#include <cerrno>

namespace FetiContact
{
  TeeStream::TeeStream()
  {
    connect();
  }

  TeeStream::~TeeStream()
  {
    try
      {
        flush();
      }
    catch (...)
      {
        // A destination that cannot be written was dropped already; nothing left to report.
      }
    reset();
  }

  void
  TeeStream::add(std::ostream &out, const std::string &name)
  {
    targets.push_back({&out, name});
    connect();
  }

  void
  TeeStream::connect()
  {
    if (!empty())
      {
        flush();
        reset();
      }
    namespace io = boost::iostreams;
    if (targets.empty())
      {
        push(io::null_sink());
        return;
      }
    for (auto t = std::next(targets.begin()); t != targets.end(); ++t)
      push(io::tee_filter<Sink>(Sink{&*t, &failure}));
    push(Sink{&targets.front(), &failure});
  }

  void
  TeeStream::drop(Target &target, Failure &failure, const int error)
  {
    if (failure.name.empty())
      {
        failure.name  = target.name.empty() ? std::string("an output stream") : target.name;
        failure.error = error;
      }
    target.out = nullptr;
  }

  std::streamsize
  TeeStream::Sink::write(const char *s, const std::streamsize n)
  {
    if (target->out == nullptr)
      return n;
    errno = 0;
    if (target->out->rdbuf()->sputn(s, n) != n)
      drop(*target, *failure, errno);
    return n;
  }

  bool
  TeeStream::Sink::flush()
  {
    if (target->out == nullptr)
      return true;
    errno = 0;
    if (!target->out->flush())
      drop(*target, *failure, errno);
    return true;
  }
} // namespace FetiContact
