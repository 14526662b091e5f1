#pragma once

#include <vector>

namespace FetiContact
{
  /**
   * The measured load balance of the subdomains among the MPI ranks: when to move subdomains
   * from one rank to another, and which.
   *
   * The subdomains are assigned in contiguous ranges (Simulator), at the start balanced by a
   * weight per subdomain (its number of cells). Equal weights are equal work only on equal
   * cores; on a machine whose cores run at different speeds (the two virtual cores of our test
   * machine differ by up to a quarter, and which one is slower changes from run to run), the
   * rank on the slower core makes every application of F wait. From the local work of each rank
   * in the applications of F since the last move (its time T_r for its weight W_r), each rank
   * has a speed v_r = W_r / T_r, and ranges whose weights are proportional to the speeds would
   * have taken max_r W'_r / v_r instead of max_r T_r.
   *
   * Moving costs the time to build the arriving subdomains (mesh, assembly, factorization) on
   * the receiving rank, while the others wait. The rule is the one of the ski-rental problem:
   * move when the time already lost to the imbalance since the last move reaches the cost of
   * the move. It loses at most twice what the best choice in hindsight loses, whatever the
   * speeds do afterwards, and a short-lived fluctuation does not move anything.
   *
   * Knows nothing of meshes or of F: it sees weights, ranges and times. Every rank calls it with
   * the same numbers (gathered) and so gets the same answer.
   */
  namespace LoadBalance
  {
    /**
     * The first subdomain of every rank's range (size n_ranks + 1, first 0, last n) such that
     * the weights of the ranges are proportional to @p speed as nearly as contiguous ranges
     * allow. @p weight_start: prefix sums of the weights (size n + 1).
     */
    std::vector<unsigned int>
    proportional_ranges(const std::vector<double> &weight_start, const std::vector<double> &speed);

    /** What propose() found. */
    struct Proposal
    {
      /** The ranges to move to (equal to the current ones when nothing is to move). */
      std::vector<unsigned int> first;
      /** The slowest rank's local time since the last move, and what the new ranges would have
       * taken [s]. */
      double time_now = 0, time_balanced = 0;
      /**
       * The time of building the arriving subdomains on the busiest receiving rank, plus the
       * fixed cost [s].
       */
      double cost = 0;
      /** Whether to move: time_now − time_balanced ≥ cost, and some subdomain changes rank. */
      bool move = false;
    };

    /**
     * @p weight_start: prefix sums of the weights (size n + 1); @p first: the current ranges
     * (size n_ranks + 1); @p local_time: every rank's local time since the last move [s];
     * @p build_time_per_weight: every rank's time to build one unit of weight [s] (measured
     * when it built its subdomains); @p fixed_cost: the part of the cost of a move that does
     * not depend on what moves (the new blocks of B and exchange lists; measured at the last
     * move) [s].
     *
     * A rank without weight or without measured time is given the mean speed of the others.
     */
    Proposal
    propose(const std::vector<double>       &weight_start,
            const std::vector<unsigned int> &first,
            const std::vector<double>       &local_time,
            const std::vector<double>       &build_time_per_weight,
            const double                     fixed_cost = 0);
  } // namespace LoadBalance
} // namespace FetiContact
