#pragma once

#include <deal.II/base/tensor.h>

#include <feticontact/contact/contact_geometry.h>
#include <feticontact/contact/contact_results.h>

#include <mpi.h>
#include <vector>

namespace FetiContact
{
  /**
   * The force of the contacts on one body: their resultant, and the sum of the absolute values
   * of the components of the nodal contact forces (the size of the forces that pass through the
   * body by contact, which the force balance judges its imbalance against).
   */
  struct ContactForceOnBody
  {
    dealii::Tensor<1, 3> force;
    double               magnitudes = 0;
  };

  /**
   * The resultant contact force of one zone: on its slave body, −Σ (λ_N n + λ_T1 t1 + λ_T2 t2),
   * and on its master, Σ over the master points of their weights times the opposite force (for
   * a rigid obstacle, the force on the obstacle, −on_slave). With mortar rows the two differ by
   * the part of the slave surface that no master triangle covers.
   */
  struct ZoneResultant
  {
    dealii::Tensor<1, 3> on_slave;
    dealii::Tensor<1, 3> on_master;
  };

  /** The contact forces per body and per zone, summed over the nodes of all ranks. */
  struct ContactForces
  {
    std::vector<ContactForceOnBody> on_body;
    std::vector<ZoneResultant>      of_zone;

    /**
     * The forces of the contact @p nodes of this rank with their @p results, summed exactly over
     * the ranks of @p comm (the same bits on any number of ranks). On a body, a master vertex's
     * prescribed component is left out: its force goes to the support, whose force K u − f holds
     * it already. Collective.
     */
    static ContactForces
    of(const std::vector<ContactNode>       &nodes,
       const std::vector<ContactNodeResult> &results,
       const unsigned int                    n_bodies,
       const unsigned int                    n_zones,
       const MPI_Comm                        comm);
  };
} // namespace FetiContact
