// The memory bandwidth one core gets, alone and with the other core doing the same: a STREAM-like
// triad a = b + 3c over three arrays of 32 Mi doubles (768 MiB), best of ten passes, counting
// 3 × 8 bytes per entry. The substitutions of FETI's local solves are bound by this bandwidth
// (doc/performance.md), so it tells how fast a machine's state lets the applications of F run
// and what two ranks on two cores can gain. Needs nothing of the project and is not in the CMake
// build:
//
//   g++ -O2 -o /tmp/stream_triad benchmarks/stream_triad.cc
//   /tmp/stream_triad && (/tmp/stream_triad & /tmp/stream_triad; wait)

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

int
main()
{
  const std::size_t   n = std::size_t(32) << 20;
  std::vector<double> a(n, 0.), b(n, 1.), c(n, 2.);
  double              best = 1e30;
  for (int pass = 0; pass < 10; ++pass)
    {
      const auto t0 = std::chrono::steady_clock::now();
      for (std::size_t i = 0; i < n; ++i)
        a[i] = b[i] + 3.0 * c[i];
      const auto t1 = std::chrono::steady_clock::now();
      best          = std::min(best, std::chrono::duration<double>(t1 - t0).count());
    }
  std::printf("triad: %.2f GB/s (a[7] = %g)\n", 3.0 * n * sizeof(double) / best / 1e9, a[7]);
  return 0;
}
