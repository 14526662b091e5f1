#include <feticontact/base/huge_pages.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#if defined(__linux__) && defined(__GLIBC__)
#  include <unistd.h>
#endif

namespace FetiContact::HugePages
{
  void
  enable_on_request(char **argv)
  {
#if defined(__linux__) && defined(__GLIBC__) && \
  (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 35))
    if (std::getenv("GLIBC_TUNABLES") != nullptr)
      return;
    if (const char *choice = std::getenv("FETICONTACT_HUGE_PAGES");
        choice != nullptr && std::strcmp(choice, "off") == 0)
      return;
    // Under valgrind /proc/self/exe is the tool, not this program.
    if (const char *preload = std::getenv("LD_PRELOAD");
        preload != nullptr && std::strstr(preload, "vgpreload") != nullptr)
      return;
    std::ifstream mode_file("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string   mode;
    std::getline(mode_file, mode);
    if (mode.find("[madvise]") == std::string::npos)
      return;
    if (setenv("GLIBC_TUNABLES", "glibc.malloc.hugetlb=1", 1) != 0)
      return;
    execv("/proc/self/exe", argv);
    // Only reached if the execution failed: go on with 4 KiB pages.
    unsetenv("GLIBC_TUNABLES");
#else
    (void)argv;
#endif
  }
} // namespace FetiContact::HugePages
