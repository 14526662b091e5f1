#include <feticontact/base/subdomain_threads.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdlib>
#include <dlfcn.h>
#include <exception>
#include <memory>
#include <mutex>
#include <sched.h>
#include <string>
#include <thread>
#include <vector>

namespace FetiContact::SubdomainThreads
{
  namespace
  {
    /**
     * Worker threads that wait for a job (a function and a number of indices) and take its
     * indices one at a time from a shared counter, the calling thread with them.
     */
    class Pool
    {
    public:
      explicit Pool(const unsigned int n_workers)
      {
        for (unsigned int t = 0; t < n_workers; ++t)
          workers.emplace_back([this] { wait_for_jobs(); });
      }

      ~Pool()
      {
        {
          std::lock_guard<std::mutex> lock(mutex);
          stopping = true;
        }
        job_posted.notify_all();
        for (auto &worker : workers)
          worker.join();
      }

      unsigned int
      size() const
      {
        return workers.size() + 1;
      }

      void
      run(const unsigned int n, const std::function<void(const unsigned int)> &work)
      {
        {
          std::lock_guard<std::mutex> lock(mutex);
          job       = &work;
          n_indices = n;
          next_index.store(0);
          failure = nullptr;
          n_busy.store(workers.size());
          generation.fetch_add(1, std::memory_order_release);
        }
        job_posted.notify_all();
        take_indices();
        // The calls of one multiplication by F take a millisecond or less: wait actively for a
        // while before sleeping.
        for (unsigned int spin = 0; spin < max_spins && n_busy.load() > 0; ++spin)
          std::this_thread::yield();
        std::unique_lock<std::mutex> lock(mutex);
        job_done.wait(lock, [this] { return n_busy.load() == 0; });
        job = nullptr;
        if (failure)
          std::rethrow_exception(failure);
      }

    private:
      void
      wait_for_jobs()
      {
        unsigned long seen = 0;
        while (true)
          {
            for (unsigned int spin = 0;
                 spin < max_spins && generation.load(std::memory_order_acquire) == seen;
                 ++spin)
              std::this_thread::yield();
            {
              std::unique_lock<std::mutex> lock(mutex);
              job_posted.wait(lock, [&] { return stopping || generation.load() != seen; });
              if (stopping)
                return;
              seen = generation.load();
            }
            take_indices();
            std::lock_guard<std::mutex> lock(mutex);
            if (n_busy.fetch_sub(1) == 1)
              job_done.notify_one();
          }
      }

      void
      take_indices()
      {
        for (unsigned int i = next_index++; i < n_indices; i = next_index++)
          try
            {
              (*job)(i);
            }
          catch (...)
            {
              std::lock_guard<std::mutex> lock(mutex);
              if (!failure)
                failure = std::current_exception();
            }
      }

      /** Rounds of std::this_thread::yield() before a thread sleeps on a condition variable. */
      static constexpr unsigned int max_spins = 20000;

      std::vector<std::thread>                       workers;
      std::mutex                                     mutex;
      std::condition_variable                        job_posted, job_done;
      const std::function<void(const unsigned int)> *job       = nullptr;
      unsigned int                                   n_indices = 0;
      std::atomic<unsigned int>                      next_index{0};
      std::atomic<unsigned int>                      n_busy{0};
      std::atomic<unsigned long>                     generation{0};
      bool                                           stopping = false;
      std::exception_ptr                             failure;
    };

    std::unique_ptr<Pool> pool;

    void
    single_threaded_blas()
    {
      if (std::getenv("OPENBLAS_NUM_THREADS") != nullptr ||
          std::getenv("OMP_NUM_THREADS") != nullptr)
        return;
      // Looked up at run time: the BLAS that Debian's alternatives give may be another one.
      using SetThreads = void (*)(int);
      if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
        set(1);
    }

    /** The cores of this rank's CPU affinity divided among the ranks on its machine. */
    unsigned int
    cores_per_rank(const MPI_Comm comm)
    {
      cpu_set_t cpus;
      CPU_ZERO(&cpus);
      int n_cores = sched_getaffinity(0, sizeof(cpus), &cpus) == 0 ? CPU_COUNT(&cpus) : 0;
      if (n_cores <= 0)
        n_cores = std::max(1u, std::thread::hardware_concurrency());
      MPI_Comm node;
      MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
      int ranks_on_node = 1;
      MPI_Comm_size(node, &ranks_on_node);
      MPI_Comm_free(&node);
      // Ranks bound to cores see only theirs; unbound ranks share the machine's.
      const int n_machine = static_cast<int>(std::thread::hardware_concurrency());
      const int share     = n_cores < n_machine ? n_cores : n_cores / ranks_on_node;
      return std::max(1, share);
    }
  } // namespace

  void
  initialize(const MPI_Comm comm)
  {
    single_threaded_blas();
    unsigned int n = cores_per_rank(comm);
    if (const char *limit = std::getenv("DEAL_II_NUM_THREADS"))
      {
        const int value = std::atoi(limit);
        if (value > 0)
          n = std::min<unsigned int>(n, value);
      }
    pool = std::make_unique<Pool>(n - 1);
  }

  unsigned int
  n_threads()
  {
    return pool ? pool->size() : 1;
  }

  void
  for_each(const unsigned int                             n,
           const std::function<void(const unsigned int)> &work,
           const bool                                     threaded)
  {
    if (!threaded || n < 2 || n_threads() == 1)
      {
        for (unsigned int i = 0; i < n; ++i)
          work(i);
        return;
      }
    pool->run(n, work);
  }
} // namespace FetiContact::SubdomainThreads
