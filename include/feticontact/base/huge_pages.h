#pragma once

namespace FetiContact::HugePages
{
  /**
   * Backs the heap with transparent huge pages (2 MiB) where the kernel offers them only on
   * request.
   *
   * A run allocates gigabytes once (the body mesh, the subdomain matrices, their Cholesky
   * factors) and touches every 4 KiB page of them for the first time: one page fault each. On a
   * kernel whose transparent huge pages are set to `madvise`
   * (/sys/kernel/mm/transparent_hugepage/enabled), 2 MiB pages need an madvise() call on the
   * memory, which glibc's malloc makes when its tunable glibc.malloc.hugetlb=1 is set. Tunables
   * are read when a process starts, so this function sets GLIBC_TUNABLES and executes the
   * program once more (same process, same arguments), before MPI is initialized.
   *
   * Nothing happens when GLIBC_TUNABLES is set already (by the user, or by this function), when
   * the kernel's mode is `always` or `never`, when the program runs under valgrind, or when the
   * environment variable FETICONTACT_HUGE_PAGES is `off`. If the new execution fails, the program
   * goes on as it is. doc/performance.md ("Huge pages") has the measured effect.
   */
  void
  enable_on_request(char **argv);
} // namespace FetiContact::HugePages
