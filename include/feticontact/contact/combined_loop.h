#pragma once

#include <deal.II/lac/vector.h>

#include <feticontact/contact/contact_solver_parameters.h>
#include <feticontact/contact/tresca_problem.h>

#include <functional>
#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * @brief Algorithm 2 of Kučera, Haslinger and Dostál: the method of successive approximations
   * and the augmented Lagrangian merged in one loop.
   *
   * Every SMALBE iteration makes one block Gauss–Seidel sweep whose λ_c block is followed by the
   * radius update g ← (1 − ω) g + ω μ λ_N (TrescaProblem::MovingSet), then one multiplier
   * update. SMALBE adapts M only while the radii stay (their relative change at most the MSA
   * tolerance) and tests its certificate of infeasibility only once they have settled after
   * three updates. The SMALBE solve is repeated, warm, with the slip bound set to μ λ_N of its
   * result, until that changes it by at most the MSA tolerance.
   *
   * @p DualVector: the dual vectors, as in TrescaProblem.
   */
  class CombinedLoop
  {
  public:
    /** What run() ends with. */
    struct Outcome
    {
      bool        converged      = false;
      bool        no_equilibrium = false;
      std::string message;
    };

    /**
     * @p slip_bound_of gives the target slip bounds μ λ_N (in the units of each node's
     * multipliers) at λ̃.
     */
    CombinedLoop(TrescaProblem                                         &tresca,
                 const Parameters::ContactSolver                       &parameters,
                 std::function<std::vector<double>(const DualVector &)> slip_bound_of);

    /** The loop's callbacks refer to this object: not copyable. */
    CombinedLoop(const CombinedLoop &) = delete;
    CombinedLoop &
    operator=(const CombinedLoop &) = delete;

    /**
     * Runs the loop warm from λ̃ = @p lambda, ν = @p nu until the slip bound changes by at most
     * @p msa_tolerance; @p monitor after every SMALBE iteration.
     */
    Outcome
    run(DualVector                   &lambda,
        dealii::Vector<double>       &nu,
        const double                  msa_tolerance,
        const TrescaProblem::Monitor &monitor);

    /** The relative change of the last radius update. */
    double
    last_change() const;

  private:
    /** The radius update between the blocks of a sweep. */
    void
    update_radii(const DualVector &lambda);

    TrescaProblem                                         &tresca;
    const Parameters::ContactSolver                       &parameters;
    std::function<std::vector<double>(const DualVector &)> slip_bound_of;
    TrescaProblem::MovingSet                               moving_set;
    double                                                 change = 0;
    /** Radius updates so far (the set is final only after three). */
    unsigned int radius_updates = 0;
  };
} // namespace FetiContact
