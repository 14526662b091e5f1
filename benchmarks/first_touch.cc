/**
 * @file first_touch.cc
 * How fast this machine hands out memory that a process touches for the first time.
 *
 * A run's setup (meshes, stiffness matrices, factors) touches its peak memory once, and on a
 * virtual machine whose balloon reports free pages to the host, the host backs every such page
 * again on its first touch. This program maps @p gib GiB, touches one byte per 4 KiB page
 * (optionally asking for transparent huge pages, as feticontact does for its heap) and then
 * writes the whole block again, and prints both times (doc/performance.md, "MPI on this
 * machine").
 *
 * Usage: first_touch [--huge-pages] [--gib N]
 */

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <sys/mman.h>

int
main(int argc, char **argv)
{
  bool        huge_pages = false;
  std::size_t gib        = 1;
  for (int i = 1; i < argc; ++i)
    {
      const std::string a = argv[i];
      if (a == "--huge-pages")
        huge_pages = true;
      else if (a == "--gib" && i + 1 < argc && std::atoi(argv[i + 1]) > 0)
        gib = std::atoi(argv[++i]);
      else
        {
          std::cerr << "first_touch: unknown or incomplete argument <" << a
                    << ">. Usage: first_touch [--huge-pages] [--gib N]" << std::endl;
          return 1;
        }
    }

  const std::size_t bytes = gib << 30;
  void *const       block =
    mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (block == MAP_FAILED)
    {
      std::cerr << "first_touch: cannot map " << gib << " GiB." << std::endl;
      return 1;
    }
  if (huge_pages)
    madvise(block, bytes, MADV_HUGEPAGE);
  char *const p = static_cast<char *>(block);

  using clock      = std::chrono::steady_clock;
  const auto start = clock::now();
  for (std::size_t i = 0; i < bytes; i += 4096)
    p[i] = 1;
  const auto   touched = clock::now();
  const double first   = std::chrono::duration<double>(touched - start).count();

  std::memset(p, 2, bytes);
  const double again = std::chrono::duration<double>(clock::now() - touched).count();

  std::cout << "first touch of " << gib << " GiB" << (huge_pages ? " (huge pages)" : "") << ": "
            << first << " s (" << bytes / first / 1e9 << " GB/s); written again: " << again
            << " s (" << bytes / again / 1e9 << " GB/s)" << std::endl;
  munmap(block, bytes);
  return 0;
}
