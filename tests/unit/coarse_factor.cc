// The factor of the coarse matrix GGᵀ kept once per node (CoarseProblem::FactorStorage::per_node,
// CholmodSolver::share_factor()) against a factor per rank, on 1 and on 3 ranks (one node):
//  - the solves with GGᵀ, the halves L⁻¹P and PᵀL⁻ᵀ, the least-norm solution and the particular
//    solution of a lower tier (its factor made on the node's first rank, which sends the
//    solutions) are the same bits;
//  - they solve GGᵀ x = b;
//  - per node, every rank of a node of several ranks maps the shared factor and no rank keeps
//    one of its own size; per rank, none is shared;
//  - a singular GGᵀ throws InputError on every rank, either way.

#include <deal.II/base/mpi.h>
#include <deal.II/lac/vector.h>

#include <feticontact/base/input_parsing.h>
#include <feticontact/feti/coarse_problem.h>
#include <feticontact/feti/dual_space.h>

#include "test_tools.h"

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace dealii;
using namespace FetiContact;

namespace
{
  constexpr unsigned int n_modes = 30, n_columns = 120;

  /**
   * The columns of G: rank p owns the columns c with c % n_ranks == p, and rank 0 all modes, so
   * that its relevant columns are all columns.
   */
  DualSpace
  columns_of_G(const MPI_Comm comm)
  {
    const unsigned int        rank    = Utilities::MPI::this_mpi_process(comm);
    const unsigned int        n_ranks = Utilities::MPI::n_mpi_processes(comm);
    std::vector<unsigned int> owned, ghosts;
    std::vector<int>          ghost_owner;
    for (unsigned int c = 0; c < n_columns; ++c)
      if (c % n_ranks == rank)
        owned.push_back(c);
      else if (rank == 0)
        {
          ghosts.push_back(c);
          ghost_owner.push_back(c % n_ranks);
        }
    return DualSpace(comm, owned, owned, ghosts, ghost_owner, n_columns);
  }

  /**
   * @p coarse from a G with every mode in several columns, without mode @p unrestrained (if <
   * n_modes): each rank the entries of its relevant columns.
   */
  void
  initialize(CoarseProblem     &coarse,
             const DualSpace   &columns,
             const unsigned int unrestrained = n_modes)
  {
    const bool root =
      Utilities::MPI::this_mpi_process(columns.partitioner()->get_mpi_communicator()) == 0;
    std::vector<CoarseProblem::Entry> entries;
    for (unsigned int c = 0; c < n_columns; ++c)
      if (columns.local_index(c) != numbers::invalid_unsigned_int)
        for (unsigned int m = 0; m < n_modes; ++m)
          if ((m * 7 + c * 3) % 5 < 2 && m != unrestrained)
            entries.push_back({m, c, 1.0 + ((m * 131 + c * 71 + m * c * 17) % 97) / 97.0});
    coarse.initialize(columns, entries, n_modes, n_columns, root ? 0 : n_modes, n_modes);
  }

  /** The numbers a coarse problem gives for fixed right-hand sides, in one vector. */
  std::vector<double>
  results(const CoarseProblem &coarse, const DualSpace &columns)
  {
    Vector<double> b(n_modes);
    for (unsigned int i = 0; i < n_modes; ++i)
      b[i] = 1.0 + (i % 7);
    std::vector<double> all;
    const auto append = [&](const Vector<double> &v) { all.insert(all.end(), v.begin(), v.end()); };
    Vector<double> x(b);
    coarse.solve_GGt(x);
    append(x);
    for (const bool transpose : {false, true})
      {
        Vector<double> half(b);
        coarse.apply_orthonormalizing_factor(half, transpose);
        append(half);
      }
    DualVector lambda = columns.vector();
    coarse.least_norm_solution(b, lambda);
    append(columns.gather(lambda));
    // Tier 0: the even columns, which restrain every mode here: a factor of their G_t G_tᵀ.
    coarse.particular_solution(
      b, [](const unsigned int c) { return c % 2; }, lambda);
    append(columns.gather(lambda));
    return all;
  }

  /** ‖GGᵀ x − b‖ / ‖b‖ for the x of solve_GGt(). */
  double
  residual(const CoarseProblem &coarse, const DualSpace &columns)
  {
    Vector<double> b(n_modes), x, r;
    DualVector     Gtx = columns.vector();
    for (unsigned int i = 0; i < n_modes; ++i)
      b[i] = 1.0 + (i % 7);
    x = b;
    coarse.solve_GGt(x);
    coarse.apply_Gt(x, Gtx);
    coarse.apply_G(Gtx, r);
    r -= b;
    return r.l2_norm() / b.l2_norm();
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                   comm    = MPI_COMM_WORLD;
  const unsigned int               n_ranks = Utilities::MPI::n_mpi_processes(comm);
  const std::string                on      = " (" + std::to_string(n_ranks) + " ranks)";

  const DualSpace columns = columns_of_G(comm);
  CoarseProblem   per_node(CoarseProblem::FactorStorage::per_node);
  CoarseProblem   per_rank(CoarseProblem::FactorStorage::per_rank);
  initialize(per_node, columns);
  initialize(per_rank, columns);

  const std::vector<double> a = results(per_node, columns), b = results(per_rank, columns);
  const bool                same =
    a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
  check(Utilities::MPI::min(same ? 1 : 0, comm) == 1,
        "per node and per rank: the same bits of (GGᵀ)⁻¹b, L⁻¹Pb, PᵀL⁻ᵀb, the least-norm and "
        "the lower tier's particular solution" +
          on);
  const double r = Utilities::MPI::max(residual(per_node, columns), comm);
  check(r < 1e-12, "GGᵀ x = b to " + sci(r) + on);

  const bool shared_everywhere =
    Utilities::MPI::min(per_node.shared_factor_bytes() > 0 ? 1 : 0, comm) == 1;
  const bool shared_nowhere =
    Utilities::MPI::max(per_node.shared_factor_bytes() > 0 ? 1 : 0, comm) == 0;
  check(n_ranks > 1 ? shared_everywhere : shared_nowhere,
        std::string("per node: ") +
          (n_ranks > 1 ? "every rank maps the shared factor" : "nothing shared on one rank") + on);
  check(Utilities::MPI::max(per_rank.shared_factor_bytes(), comm) == 0,
        "per rank: nothing shared" + on);

  for (const auto storage :
       {CoarseProblem::FactorStorage::per_node, CoarseProblem::FactorStorage::per_rank})
    {
      CoarseProblem singular(storage);
      bool          thrown = false;
      try
        {
          initialize(singular, columns, 4);
        }
      catch (const InputError &)
        {
          thrown = true;
        }
      check(Utilities::MPI::min(thrown ? 1 : 0, comm) == 1,
            std::string("an unrestrained mode: InputError on every rank, ") +
              (storage == CoarseProblem::FactorStorage::per_node ? "per node" : "per rank") + on);
    }
  return n_failures;
}
