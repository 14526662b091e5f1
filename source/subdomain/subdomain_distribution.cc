#include <deal.II/base/mpi.h>

#include <feticontact/base/block_partition.h>
#include <feticontact/base/subdomain_threads.h>
#include <feticontact/subdomain/subdomain_distribution.h>

#include <numeric>
#include <utility>

namespace FetiContact
{
  namespace SubdomainDistribution
  {
    std::vector<unsigned int>
    owners(const std::vector<std::unique_ptr<Body>> &bodies,
           const std::vector<unsigned int>          &first_subdomain,
           const MPI_Comm                            comm)
    {
      // Blocks are numbered lexicographically, so a range of them is a slab, and the rows of B
      // between two ranks' sets of subdomains, whose terms are exchanged in every multiplication
      // by F (DualProblem), are those of a few planar cuts. (METIS numbers its parts without
      // such a guarantee: there the exchange can be larger.)
      const unsigned int        n = first_subdomain.back();
      std::vector<unsigned int> cells_before(n + 1, 0);
      for (const auto &body : bodies)
        for (unsigned int p = 0; p < body->partition.n_parts; ++p)
          cells_before[first_subdomain[body->index] + p + 1] = body->cells_per_part[p];
      std::partial_sum(cells_before.begin(), cells_before.end(), cells_before.begin());
      const BlockPartition      ranges  = BlockPartition::balanced(comm, cells_before);
      const unsigned int        n_ranks = dealii::Utilities::MPI::n_mpi_processes(comm);
      std::vector<unsigned int> owner(n, 0);
      for (unsigned int r = 0; r < n_ranks; ++r)
        for (unsigned int s = ranges.firsts()[r]; s < ranges.firsts()[r + 1]; ++s)
          owner[s] = r;
      return owner;
    }

    std::vector<std::unique_ptr<Subdomain>>
    make_subdomains(const std::vector<std::unique_ptr<Body>> &bodies,
                    const std::vector<unsigned int>          &first_subdomain,
                    const std::vector<unsigned int>          &owner,
                    const unsigned int                        rank,
                    const bool                                eliminate_prescribed,
                    const dealii::FiniteElement<3>           &fe)
    {
      std::vector<std::pair<const Body *, unsigned int>> parts;
      for (const auto &body : bodies)
        for (unsigned int p = 0; p < body->partition.n_parts; ++p)
          if (owner[first_subdomain[body->index] + p] == rank)
            parts.emplace_back(body.get(), p);
      std::vector<std::vector<std::vector<unsigned int>>> parts_of_vertex(bodies.size());
      for (const auto &[body, p] : parts)
        if (parts_of_vertex[body->index].empty())
          parts_of_vertex[body->index] = body->parts_of_mesh_vertices();
      // One subdomain per call on the subdomain threads.
      std::vector<std::unique_ptr<Subdomain>> subdomains(parts.size());
      SubdomainThreads::for_each(parts.size(), [&](const unsigned int i) {
        const auto &[body, p] = parts[i];
        subdomains[i] =
          std::make_unique<Subdomain>(*body,
                                      body->part_cells(p, parts_of_vertex[body->index]),
                                      first_subdomain[body->index] + p,
                                      eliminate_prescribed,
                                      fe);
      });
      return subdomains;
    }

    std::vector<unsigned int>
    mode_offsets(const std::vector<Subdomain *> &owned,
                 const unsigned int              n_subdomains,
                 const MPI_Comm                  comm)
    {
      std::vector<double> n_modes(n_subdomains, 0.0);
      for (auto *s : owned)
        n_modes[s->global_index] = s->R.n();
      dealii::Utilities::MPI::sum(dealii::make_array_view(std::as_const(n_modes)),
                                  comm,
                                  dealii::make_array_view(n_modes));
      std::vector<unsigned int> offset(n_modes.size() + 1, 0);
      for (unsigned int s = 0; s < n_modes.size(); ++s)
        offset[s + 1] = offset[s] + static_cast<unsigned int>(n_modes[s]);
      return offset;
    }
  } // namespace SubdomainDistribution
} // namespace FetiContact
