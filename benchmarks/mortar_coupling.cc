// mortar_coupling [--sizes N1,N2,...] [--repeats R]: the time of Mortar::couple (R-tree search,
// clipping and integration) for a slave square split N × N into 2N² triangles against a master
// square split ⌊1.4 N⌋ × ⌊1.4 N⌋ with the other diagonals, 0.001 apart, per slave node; the median
// of R runs. Prints one CSV row per size: n_slave_nodes, n_master_nodes, segments, seconds,
// microseconds per slave node (run by benchmarks/mortar_cost.py for doc/validation.md).

#include <feticontact/contact/mortar.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using namespace dealii;
using namespace FetiContact;

namespace
{
  Mortar::Surface
  square(const unsigned int n, const double z, const double up, const bool flip)
  {
    Mortar::Surface s;
    for (unsigned int j = 0; j <= n; ++j)
      for (unsigned int i = 0; i <= n; ++i)
        s.points.emplace_back(double(i) / n, double(j) / n, z);
    const auto at = [&](unsigned int i, unsigned int j) { return j * (n + 1) + i; };
    for (unsigned int j = 0; j < n; ++j)
      for (unsigned int i = 0; i < n; ++i)
        if (flip)
          {
            s.triangles.push_back({{at(i, j), at(i + 1, j), at(i, j + 1)}});
            s.triangles.push_back({{at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)}});
          }
        else
          {
            s.triangles.push_back({{at(i, j), at(i + 1, j), at(i + 1, j + 1)}});
            s.triangles.push_back({{at(i, j), at(i + 1, j + 1), at(i, j + 1)}});
          }
    Tensor<1, 3> outward;
    outward[2] = up;
    Mortar::compute_normals(s, std::vector<Tensor<1, 3>>(s.triangles.size(), outward));
    return s;
  }
} // namespace

int
main(int argc, char **argv)
{
  std::vector<unsigned int> sizes{20, 40, 80, 160, 320};
  unsigned int              repeats = 3;
  for (int i = 1; i + 1 < argc; i += 2)
    {
      const std::string option = argv[i];
      if (option == "--sizes")
        {
          sizes.clear();
          std::istringstream list(argv[i + 1]);
          std::string        item;
          while (std::getline(list, item, ','))
            sizes.push_back(std::stoi(item));
        }
      else if (option == "--repeats")
        repeats = std::stoi(argv[i + 1]);
      else
        {
          std::cerr << "unknown option " << option << std::endl;
          return 1;
        }
    }
  std::cout << "n_slave_nodes,n_master_nodes,segments,seconds,microseconds_per_slave_node\n";
  for (const unsigned int n : sizes)
    {
      const auto          slave  = square(n, 0.0, -1, false);
      const auto          master = square(static_cast<unsigned int>(1.4 * n), -0.001, 1, true);
      std::vector<double> times;
      Mortar::Statistics  statistics;
      for (unsigned int r = 0; r < repeats; ++r)
        {
          const auto start = std::chrono::steady_clock::now();
          const auto c     = Mortar::couple(slave, master, 0.5 / n, statistics);
          times.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
          if (c.size() != slave.points.size())
            return 1;
        }
      std::sort(times.begin(), times.end());
      const double t = times[times.size() / 2];
      std::cout << slave.points.size() << ',' << master.points.size() << ','
                << statistics.n_segments << ',' << t << ',' << 1e6 * t / slave.points.size()
                << std::endl;
    }
  return 0;
}
