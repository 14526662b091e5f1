// exact_sum [--sizes N1,N2,...] [--repeats R]: the time per term of a dot product of two vectors
// of N random numbers, summed in order (a plain loop), exactly term by term (ReproducibleReductions
// on a partitioner without chunks: every product into ExactSum) and by chunks of 1000 entries (a
// ReproduciblePartitioner with chunks, as the FETI dual vectors: plain sums within a chunk, the
// chunks' sums exactly),
// the median of R repetitions (doc/performance.md, "Reproducible sums").

#include <feticontact/base/reproducible_partitioner.h>

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace FetiContact;

namespace
{
  template <typename F>
  double
  median_ns_per_term(const F &f, const unsigned int n, const unsigned int repeats)
  {
    std::vector<double> t;
    const unsigned int  inner = std::max(1u, 4000000u / n);
    for (unsigned int r = 0; r < repeats; ++r)
      {
        const auto start = std::chrono::steady_clock::now();
        for (unsigned int k = 0; k < inner; ++k)
          f();
        t.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / inner /
          n * 1e9);
      }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
  }
} // namespace

int
main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);
  std::vector<unsigned int> sizes{10000, 100000, 1000000};
  unsigned int              repeats = 7;
  for (int i = 1; i + 1 < argc; i += 2)
    {
      const std::string option = argv[i];
      if (option == "--repeats")
        repeats = std::stoi(argv[i + 1]);
      else if (option == "--sizes")
        {
          sizes.clear();
          std::stringstream list(argv[i + 1]);
          for (std::string item; std::getline(list, item, ',');)
            sizes.push_back(std::stoi(item));
        }
    }
  std::cout << "n,plain_ns_per_term,exact_ns_per_term,chunked_ns_per_term" << std::endl;
  for (const unsigned int n : sizes)
    {
      std::vector<unsigned int> index(n);
      for (unsigned int i = 0; i < n; ++i)
        index[i] = i;
      const auto layout = std::make_shared<const dealii::Utilities::MPI::Partitioner>(n);
      std::vector<unsigned int> chunk_of_entry(n);
      for (unsigned int i = 0; i < n; ++i)
        chunk_of_entry[i] = i / 1000;
      const auto chunked_layout = std::make_shared<const ReproduciblePartitioner>(
        MPI_COMM_SELF, 0, n, dealii::IndexSet(n), index, chunk_of_entry);
      DistributedVector                a(layout), b(layout), ac(chunked_layout), bc(chunked_layout);
      std::mt19937                     engine(1);
      std::normal_distribution<double> normal;
      for (unsigned int i = 0; i < n; ++i)
        {
          a[i]  = normal(engine);
          b[i]  = 1e3 * normal(engine);
          ac[i] = a[i];
          bc[i] = b[i];
        }
      volatile double sink  = 0;
      const double    plain = median_ns_per_term(
        [&]() {
          double s = 0;
          for (unsigned int i = 0; i < n; ++i)
            s += a[i] * b[i];
          sink = s;
        },
        n,
        repeats);
      using ReproducibleReductions::dot;
      const double exact   = median_ns_per_term([&]() { sink = dot(a, b); }, n, repeats);
      const double chunked = median_ns_per_term([&]() { sink = dot(ac, bc); }, n, repeats);
      std::cout << n << ',' << std::setprecision(3) << plain << ',' << exact << ',' << chunked
                << std::endl;
    }
  MPI_Finalize();
}
