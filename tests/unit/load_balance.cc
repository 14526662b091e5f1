// The measured load balance (run on 1 and on 3 ranks):
//  - proportional_ranges: contiguous ranges that cover all subdomains, with weights proportional
//    to the speeds (each off by at most the heaviest subdomain); equal speeds give the
//    balanced ranges of BlockPartition;
//  - propose: no move on equal speeds; on a rank twice as slow as the other the move to the
//    ranges 1 : 2, with the time it would have taken; no move while the time lost is below the
//    cost of the move (the ski-rental rule), a move once it reaches it, but not if the fixed
//    part of the cost makes the cost larger than the time lost; a rank without time
//    does not stop the others from being balanced;
//  - DualProblem::reassign: after moving subdomains between the ranks (built again on their new
//    rank), F x is the same bits as before, also when the move happens inside apply_F through
//    the periodic check.

#include <deal.II/base/mpi.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>

#include <feticontact/base/block_partition.h>
#include <feticontact/feti/dual_problem.h>
#include <feticontact/feti/equality_constraints.h>
#include <feticontact/feti/load_balance.h>

#include "test_tools.h"

#include <algorithm>
#include <memory>
#include <random>

using namespace dealii;
using namespace FetiContact;

namespace
{
  std::vector<double>
  prefix_sums(const std::vector<double> &weight)
  {
    std::vector<double> start(weight.size() + 1, 0.);
    for (unsigned int i = 0; i < weight.size(); ++i)
      start[i + 1] = start[i] + weight[i];
    return start;
  }

  void
  check_ranges()
  {
    std::mt19937                           random(3);
    std::uniform_real_distribution<double> uniform(1, 4);
    std::vector<double>                    weight(97);
    for (auto &w : weight)
      w = uniform(random);
    const auto   start    = prefix_sums(weight);
    const double heaviest = *std::max_element(weight.begin(), weight.end());
    for (const auto &speed : std::vector<std::vector<double>>{
           {1.}, {1., 1.}, {1., 2.}, {3., 1., 2.}, {1., 1., 1., 1., 5.}})
      {
        const auto first = LoadBalance::proportional_ranges(start, speed);
        bool       ok    = first.size() == speed.size() + 1 && first.front() == 0 &&
                  first.back() == weight.size() && std::is_sorted(first.begin(), first.end());
        double total_speed = 0;
        for (const double v : speed)
          total_speed += v;
        double worst = 0;
        for (unsigned int r = 0; ok && r < speed.size(); ++r)
          {
            const double share = start.back() * speed[r] / total_speed;
            worst = std::max(worst, std::abs(start[first[r + 1]] - start[first[r]] - share));
          }
        check(ok && worst <= heaviest * (speed.size() - 1),
              "proportional ranges for " + std::to_string(speed.size()) +
                " speeds cover the subdomains; largest deviation from the share " + sci(worst) +
                " (heaviest subdomain " + sci(heaviest) + ")");
      }
    // Equal speeds: the ranges of BlockPartition::balanced, which the Simulator starts from.
    std::vector<unsigned int> cells(41);
    for (unsigned int i = 0; i < cells.size(); ++i)
      cells[i] = 100 + (7 * i) % 13;
    std::vector<unsigned int> cell_start(cells.size() + 1, 0);
    for (unsigned int i = 0; i < cells.size(); ++i)
      cell_start[i + 1] = cell_start[i] + cells[i];
    const std::vector<double> cell_weight(cells.begin(), cells.end());
    const auto equal = LoadBalance::proportional_ranges(prefix_sums(cell_weight), {1., 1., 1.});
    int        n_ranks_here = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &n_ranks_here);
    if (n_ranks_here == 3)
      check(equal == BlockPartition::balanced(MPI_COMM_WORLD, cell_start).firsts(),
            "equal speeds give the ranges of BlockPartition::balanced");
  }

  void
  check_proposals()
  {
    // 60 subdomains of weight 1 on two ranks, 30 each; one unit of weight costs 0.01 s to build.
    const auto                      start = prefix_sums(std::vector<double>(60, 1.));
    const std::vector<unsigned int> first{0, 30, 60};
    const std::vector<double>       build{0.01, 0.01};

    auto p = LoadBalance::propose(start, first, {3., 3.}, build);
    check(!p.move && p.first == first && p.time_now == 3. && p.time_balanced == 3.,
          "equal speeds: no move");

    // Rank 1 twice as slow: 30 s against 60 s; the ranges 40 : 20 take 40 s. Moving 10
    // subdomains to rank 0 costs 0.1 s, far less than the 20 s lost.
    p = LoadBalance::propose(start, first, {30., 60.}, build);
    check(p.move && p.first == std::vector<unsigned int>({0, 40, 60}) &&
            std::abs(p.time_balanced - 40.) < 1e-12 && std::abs(p.cost - 0.1) < 1e-12,
          "a rank twice as slow: ranges 0 40 60, " + sci(p.time_balanced) + " s instead of " +
            sci(p.time_now) + " s, cost " + sci(p.cost) + " s");

    // The same ratio after a short time: 0.03 against 0.06 s lost 0.02 s < 0.1 s: wait.
    p = LoadBalance::propose(start, first, {0.03, 0.06}, build);
    check(!p.move && p.first == first && std::abs(p.time_now - p.time_balanced - 0.02) < 1e-12,
          "the time lost (" + sci(p.time_now - p.time_balanced) + " s) below the cost (" +
            sci(p.cost) + " s): no move");
    // ... and once the time lost reaches the cost (0.2 against 0.4 s: 0.133 s lost).
    p = LoadBalance::propose(start, first, {0.2, 0.4}, build);
    check(p.move, "the time lost reaches the cost: move");
    // ... but not when the fixed part of the cost of a move makes it larger than that.
    p = LoadBalance::propose(start, first, {0.2, 0.4}, build, 0.05);
    check(!p.move && std::abs(p.cost - 0.15) < 1e-12,
          "with a fixed cost of 0.05 s the move costs " + sci(p.cost) + " s: no move");

    // Three ranks, the middle one without measured time: it gets the mean speed of the others.
    const std::vector<unsigned int> first3{0, 20, 40, 60};
    p = LoadBalance::propose(start, first3, {20., 0., 40.}, {0.01, 0.01, 0.01});
    check(p.move && p.first.size() == 4 && p.first[1] > 20 && p.first[3] == 60,
          "a rank without time: the others still balanced (ranges " + std::to_string(p.first[1]) +
            ", " + std::to_string(p.first[2]) + ")");

    // One rank: nothing to balance.
    p = LoadBalance::propose(start, {0, 60}, {5.}, {0.01});
    check(!p.move, "one rank: no move");
  }

  /** F x on the brick with the subdomains spread over the ranks, before and after moves. */
  void
  check_reassign()
  {
    const MPI_Comm     comm    = MPI_COMM_WORLD;
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
    const unsigned int rank    = Utilities::MPI::this_mpi_process(comm);
    const FESystem<3>  fe(FE_SimplexP<3>(1), 3);
    const MappingFE<3> mapping(FE_SimplexP<3>(1));
    const auto         scene = scene_from_text(brick_text("set Method = blocks\nset Blocks = 6, 1, 1"));
    std::vector<std::unique_ptr<Body>> bodies;
    bodies.push_back(std::make_unique<Body>(scene.bodies[0], 0));
    bodies[0]->setup();
    const unsigned int n_sub = bodies[0]->partition.n_parts;
    const DualRows     rows  = build_equality_rows(bodies, {0, n_sub}, true);

    std::map<unsigned int, std::unique_ptr<Subdomain>> built;
    const auto owned_for = [&](const std::vector<unsigned int> &first) {
      // Drop what leaves, build what arrives.
      for (auto it = built.begin(); it != built.end();)
        it = (it->first < first[rank] || it->first >= first[rank + 1]) ? built.erase(it) : ++it;
      std::vector<Subdomain *> owned;
      for (unsigned int s = first[rank]; s < first[rank + 1]; ++s)
        {
          if (built.count(s) == 0)
            {
              built[s] = std::make_unique<Subdomain>(*bodies[0], s, s, false, fe);
              built[s]->assemble(mapping);
              built[s]->factorize("cholmod");
            }
          owned.push_back(built[s].get());
        }
      return owned;
    };
    // Ranges: all on the last rank first, then every rank a share, then shifted.
    std::vector<unsigned int> start_ranges(n_ranks + 1, 0), spread(n_ranks + 1, n_sub),
      shifted(n_ranks + 1, n_sub);
    start_ranges.back() = n_sub;
    for (unsigned int r = 0; r < n_ranks; ++r)
      {
        spread[r]  = r * n_sub / n_ranks;
        shifted[r] = r == 0 ? 0 : std::min(n_sub, spread[r] + 1);
      }
    std::vector<unsigned int> mode_offset{0};
    for (unsigned int s = 0; s < n_sub; ++s)
      mode_offset.push_back(mode_offset.back() + 6);

    DualProblem    dual(comm, owned_for(start_ranges), mode_offset, rows);
    Vector<double> x(dual.size()), Fx, Fx_moved;
    std::mt19937   random(11);
    std::uniform_real_distribution<double> uniform(-1, 1);
    for (auto &v : x)
      v = uniform(random);
    dual.apply_F(x, Fx);
    bool same = true;
    for (const auto &ranges : {spread, shifted, start_ranges})
      {
        dual.reassign(owned_for(ranges));
        dual.apply_F(x, Fx_moved);
        same = same && std::equal(Fx.begin(), Fx.end(), Fx_moved.begin());
      }
    check(same,
          "F x the same bits with the subdomains moved among " + std::to_string(n_ranks) +
            " ranks (" + std::to_string(n_sub) + " subdomains, three moves)");

    // A move inside apply_F, from the periodic check (every second application).
    unsigned int n_checks = 0;
    dual.set_periodic_check(
      [&]() {
        ++n_checks;
        dual.reassign(owned_for(n_checks % 2 ? spread : shifted));
      },
      2);
    same = true;
    for (unsigned int i = 0; i < 6; ++i)
      {
        dual.apply_F(x, Fx_moved);
        same = same && std::equal(Fx.begin(), Fx.end(), Fx_moved.begin());
      }
    check(same && n_checks == 3,
          "F x the same bits with moves from the periodic check (" + std::to_string(n_checks) +
            " checks in 6 applications)");
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  check_ranges();
  check_proposals();
  check_reassign();
  return n_failures;
}
