#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <feticontact/feti/local_dual_rows.h>

#include <algorithm>

namespace FetiContact
{
  using namespace dealii;

  LocalDualRows::LocalDualRows(const DualProblem &dual)
    : dual(dual)
    , space(dual.space())
  {}

  DualVector
  LocalDualRows::vector() const
  {
    return space.vector();
  }

  const DualVector &
  LocalDualRows::h() const
  {
    return dual.h;
  }

  const DualVector &
  LocalDualRows::c() const
  {
    return dual.c;
  }

  DualVector LocalDualRows::restrict(const Vector<double> &all) const
  {
    return space.restrict(all);
  }

  Vector<double>
  LocalDualRows::gather(const DualVector &x) const
  {
    return space.gather(x);
  }

  unsigned int
  LocalDualRows::local_index(const unsigned int row) const
  {
    return space.owned_index(row);
  }

  unsigned int
  LocalDualRows::n_local() const
  {
    return space.n_owned();
  }

  LocalDualRows::Block
  LocalDualRows::block(const unsigned int first, const unsigned int n) const
  {
    Block                          b;
    const ReproduciblePartitioner &p = *space.partitioner();
    b.first                          = first;
    b.n                              = n;
    // The owned rows of the block in the order of the vectors (by chunk, then number), with
    // their chunks.
    std::vector<unsigned int> key, chunk;
    unsigned int              chunk_number = 0;
    for (unsigned int i = 0; i < p.locally_owned_size(); ++i)
      {
        if (p.chunked() && p.new_chunk[p.run_of_entry[i]] && p.run_start[p.run_of_entry[i]] == i)
          ++chunk_number;
        if (p.key(i) >= first && p.key(i) < first + n)
          {
            b.entries.push_back(i);
            key.push_back(p.key(i) - first);
            if (p.chunked())
              chunk.push_back(chunk_number);
          }
      }
    unsigned long long n_owned = key.size(), offset = 0;
    const MPI_Comm     comm = p.get_mpi_communicator();
    MPI_Exscan(&n_owned, &offset, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      offset = 0;
    b.partitioner = std::make_shared<const ReproduciblePartitioner>(
      comm, offset, n, IndexSet(n), std::move(key), chunk);
    return b;
  }

  unsigned int
  LocalDualRows::Block::index_of(const unsigned int i) const
  {
    const auto it = std::lower_bound(entries.begin(), entries.end(), i);
    AssertThrow(it != entries.end() && *it == i,
                ExcMessage("LocalDualRows::Block: entry " + std::to_string(i) +
                           " is not in the block."));
    return it - entries.begin();
  }

  DualVector
  LocalDualRows::Block::vector() const
  {
    return DualVector(partitioner);
  }

  void
  LocalDualRows::Block::extract(const DualVector &full, DualVector &part) const
  {
    if (part.get_partitioner() != partitioner)
      part.reinit(partitioner);
    for (unsigned int j = 0; j < entries.size(); ++j)
      part.local_element(j) = full.local_element(entries[j]);
  }

  void
  LocalDualRows::Block::insert(const DualVector &part, DualVector &full) const
  {
    for (unsigned int j = 0; j < entries.size(); ++j)
      full.local_element(entries[j]) = part.local_element(j);
  }

  void
  LocalDualRows::sum_over_ranks(std::vector<unsigned int> &counts) const
  {
    Utilities::MPI::sum(ArrayView<const unsigned int>(counts.data(), counts.size()),
                        space.partitioner()->get_mpi_communicator(),
                        ArrayView<unsigned int>(counts.data(), counts.size()));
    ++space.partitioner()->n_reductions;
  }

  double
  LocalDualRows::max_over_ranks(const double local) const
  {
    ++space.partitioner()->n_reductions;
    return Utilities::MPI::max(local, space.partitioner()->get_mpi_communicator());
  }

  void
  LocalDualRows::sum_over_ranks(std::vector<ExactSum> &sums) const
  {
    ++space.partitioner()->n_reductions;
    ExactSum::sum_over_ranks(sums, space.partitioner()->get_mpi_communicator());
  }

} // namespace FetiContact
