#pragma once

#include <feticontact/contact/contact_geometry.h>
#include <feticontact/scene/body.h>

#include <memory>
#include <mpi.h>
#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * The outcome of test_load_balance(): whether contact forces that the friction law allows
   * can balance the loads on the rigid motions that the prescribed displacements leave free.
   */
  struct LoadBalance
  {
    enum class Outcome
    {
      /** No body has a free rigid motion, or forces within the law's sets balance the loads. */
      balanced,
      /** A certificate proves that no such forces exist: the scene has no equilibrium. */
      impossible,
      /** Neither shown within the iteration limit (the solve decides). */
      undecided
    };
    Outcome outcome = Outcome::balanced;
    /** min ‖Wp − e‖ / ‖e‖ found over the admissible contact forces p. */
    double relative_residual = 0;
    /**
     * ‖e‖: the loads' resultant on the free motions (forces, and moments divided by the
     * body's size), N.
     */
    double load_resultant = 0;
    /** The certificate α (‖α‖ = 1): the work αᵀe that the loads do on the rigid motion α. */
    double load_work = 0;
    /**
     * The contact forces within the law's sets can do more work on α only if the sum of
     * their magnitudes exceeds this bound (N; infinite when they can do none).
     */
    double force_bound = 0;
    /** The rigid motion α as text: the bodies it moves and their translation and rotation. */
    std::string  motion;
    unsigned int iterations = 0;
  };

  /**
   * A necessary condition of equilibrium, tested before any solve and independent of the
   * decomposition and the algorithm: the loads f must be balanced on every free rigid motion
   * of every body by contact forces p_k = (λ_N, λ_T1, λ_T2) in the sets of the friction law:
   * the cones ‖λ_T‖ ≤ μ λ_N (Coulomb) or λ_N ≥ 0, ‖λ_T‖ ≤ g (Tresca, @p tresca_slip_bound ≥ 0).
   * With W the work of the contact forces on the free motions (−p_k on the slave, +p_k on the
   * master) and e the negative work of the loads, the test minimizes ½‖Wp − e‖² over those
   * sets by accelerated projected gradients (FISTA with backtracking and restarts). A nonzero
   * minimum gives α = −r/‖r‖ (r = Wp − e), and α is a certificate when the loads do more work
   * on it than any admissible contact forces whose magnitudes sum to less than 10⁴ ‖e‖:
   * αᵀe > Λ max_k s_k + Σ_k c_k with Λ = 10⁴ ‖e‖ (s_k, c_k from the node's set:
   * s_k = ‖Π_K(W_kᵀα)‖ for a cone, s_k = max(y_N, 0) and c_k = g‖y_T‖ for Tresca).
   */
  /**
   * The data of test_load_balance() (the free rigid motions of the bodies, the work of the
   * loads on them, the work of every contact node's forces), built once, for tests with
   * different sets: the cones of the friction law, or Tresca sets with one slip bound per node
   * (the slip bounds of an MSA step, g = μ λ_N of the previous one). Knows nothing of the FETI
   * layer: the contact solver calls it with the bounds it is about to solve for.
   */
  class LoadBalanceTest
  {
  public:
    /**
     * The test of the contact nodes @p nodes: all nodes (@p comm = MPI_COMM_SELF), or this
     * rank's, each node on one rank of @p comm (a node's chunk, its home part, on one rank).
     * Then the tests are collective and give the same result, to the bit, on every rank and on
     * any number of ranks.
     */
    LoadBalanceTest(const std::vector<std::unique_ptr<Body>> &bodies,
                    const std::vector<ContactNode>           &nodes,
                    const MPI_Comm                            comm);
    ~LoadBalanceTest();
    /** Whether any body has a free rigid motion on which the loads do work. */
    bool
    has_free_motions() const;
    /** The test with the friction cones ‖λ_T‖ ≤ μ λ_N. */
    LoadBalance
    coulomb(const unsigned int max_iterations = 2000);
    /**
     * The test with λ_N ≥ 0, ‖λ_T‖ ≤ g_k (@p slip_bounds by contact node of this object's
     * nodes, forces in N; nodes without friction get g = 0).
     */
    LoadBalance
    tresca(const std::vector<double> &slip_bounds, const unsigned int max_iterations = 2000);

  private:
    struct Problem;
    std::unique_ptr<Problem> problem;
  };

  LoadBalance
  test_load_balance(const std::vector<std::unique_ptr<Body>> &bodies,
                    const std::vector<ContactNode>           &nodes,
                    const double                              tresca_slip_bound,
                    const unsigned int                        max_iterations = 2000);
} // namespace FetiContact
