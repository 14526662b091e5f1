#pragma once

#include <deal.II/base/conditional_ostream.h>

#include <feticontact/contact/contact_forces.h>
#include <feticontact/contact/contact_nodes.h>
#include <feticontact/contact/contact_results.h>
#include <feticontact/contact/contact_rows.h>
#include <feticontact/contact/load_balance.h>
#include <feticontact/feti/dual_problem.h>
#include <feticontact/feti/local_dual_rows.h>
#include <feticontact/scene/body.h>
#include <feticontact/scene/contact_parameters.h>

#include <array>
#include <functional>
#include <memory>
#include <mpi.h>
#include <optional>
#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * Calls @p f(row, x_row) for every entry that this rank holds of the dual vector @p x, with
   * the row of λ = [λ_T; λ_N; λ_E] it belongs to. With ContactState::multiplier() the one place
   * where the run reads the entries of a dual vector by their rows.
   */
  void
  for_each_held_row(const DualVector                                            &x,
                    const std::function<void(const unsigned int, const double)> &f);

  /**
   * What the contact nodes of a solution give: per node this rank holds its forces, gap, slip
   * and status, the checks of the contact conditions over all ranks, and the contact forces per
   * body and per zone.
   */
  struct ContactEvaluation
  {
    /** Per held contact node: the forces, the gap, the slip and the status. */
    std::vector<ContactNodeResult> results;
    /** The contact conditions checked from u and the forces (the penetration of every vertex). */
    ContactCheck check;
    /** The forces of the contacts on each body and the resultant of each zone. */
    ContactForces forces;
  };

  /**
   * The contact state of a run: the contact nodes that the search found on this rank's home
   * vertices, the contact surfaces and what the search reported per zone (find()); the nodes
   * whose rows of B this rank holds in the dual problem (hold()) and the multipliers λ at those
   * rows (multiplier()); the load-balance test of the free rigid motions; and from a solution the
   * nodes' forces, gaps and statuses, the contact check and the contact forces per body and zone
   * (evaluate()).
   */
  class ContactState
  {
  public:
    /**
     * The contact nodes of the zones of @p contact on @p bodies: every rank finds the nodes of
     * its home vertices, whose rows it will hold. Collective.
     */
    void
    find(const std::vector<std::unique_ptr<Body>> &bodies,
         const Parameters::Contact                &contact,
         const MPI_Comm                            comm);

    /** The log lines of what the search found per zone. */
    void
    report_zones(dealii::ConditionalOStream &pcout) const;

    /**
     * Throws InputError naming the body and its free rigid motions if a body of @p bodies that
     * only contact could hold has no contact node (as slave or master): the coarse problem would
     * be singular. Collective.
     */
    void
    check_bodies_held(const std::vector<std::unique_ptr<Body>> &bodies,
                      const Parameters::Contact                &contact,
                      const MPI_Comm                            comm) const;

    /**
     * The test that contact forces within the friction law's sets can balance the loads on the
     * free rigid motions of @p bodies (LoadBalanceTest, kept for the solve): with a
     * @p tresca_slip_bound the bound g of every node (Tresca), else the friction cones (Coulomb).
     * Collective.
     */
    LoadBalance
    test_load_balance(const std::vector<std::unique_ptr<Body>> &bodies,
                      const std::optional<double>               tresca_slip_bound,
                      const MPI_Comm                            comm);

    /**
     * The message of a load balance proved impossible, with the slave vertices that the contact
     * search left without a master (uncoupled_vertices_text()).
     */
    std::string
    no_equilibrium_message(const LoadBalance &balance, const bool tresca) const;

    /**
     * The nodes whose rows this rank holds in the dual problem @p dual with the rows laid out
     * by @p layout: each node on the rank of its home subdomain (the lowest copy of its slave
     * vertex; @p owner: the rank of every subdomain, @p first_subdomain: of every body). Checks
     * that a rank holds the normal rows of exactly its nodes. Collective.
     */
    void
    hold(const DualProblem               &dual,
         const DualLayout                &layout,
         const std::vector<unsigned int> &owner,
         const std::vector<unsigned int> &first_subdomain,
         const MPI_Comm                   comm);

    /** λ of row @p row of a contact node this rank holds (hold()), from the solution @p lambda. */
    double
    multiplier(const DualVector &lambda, const unsigned int row) const;

    /**
     * The vertices whose displacements evaluate() reads, each as (body, body vertex, home part):
     * those of the contact surfaces' triangles, of the uncoupled vertices, and of the held nodes
     * and their master vertices.
     */
    std::vector<std::array<unsigned int, 3>>
    vertices_read() const;

    /**
     * The held nodes' results from the solution @p lambda and the displacements @p surface_u of
     * vertices_read(), the contact check (with the penetration of the contact surfaces and
     * @p vertex_penetration, the depth of the deepest vertex in a rigid obstacle, relative to
     * @p u_max; @p largest_cell: the largest cell diameter of all bodies) and the contact forces.
     * With a @p tresca_slip_bound the bound of nodes with friction is that slip bound. Collective.
     */
    ContactEvaluation
    evaluate(const DualVector           &lambda,
             const VertexDisplacements  &surface_u,
             const double                u_max,
             const double                vertex_penetration,
             const double                largest_cell,
             const Parameters::Contact  &contact,
             const std::optional<double> tresca_slip_bound,
             const unsigned int          n_bodies,
             const MPI_Comm              comm) const;

    /** The contact nodes this rank found (find()): those of its home vertices. */
    const std::vector<ContactNode> &
    nodes() const
    {
      return found;
    }

    /** The number of contact nodes of all ranks. */
    unsigned int
    n_nodes() const
    {
      return n_found;
    }

    const ContactSurfaces &
    surfaces() const
    {
      return contact_surfaces;
    }

    /** The contact nodes whose rows this rank holds, with their layout (hold()). */
    const HeldContactNodes &
    held() const
    {
      return held_nodes;
    }

    /** The load-balance test (test_load_balance()), or null before it or without contact. */
    LoadBalanceTest *
    load_balance()
    {
      return load_balance_test.get();
    }

    /** The memory of the found and the held contact nodes and of the surfaces [bytes]. */
    std::size_t
    memory_consumption() const;

  private:
    /**
     * For a message: per zone whose search left slave vertices without a master (or an
     * obstacle) within its search distance, their number and the distance; "" if none.
     */
    std::string
    uncoupled_vertices_text() const;

    std::vector<ContactNode> found;
    unsigned int             n_found = 0;
    ContactSurfaces          contact_surfaces;
    /** What the contact search found per zone (counts over all ranks). */
    std::vector<ZoneReport> zone_reports;
    /** Per contact zone: whether its rows are mortar rows (the mortar overlap check). */
    std::vector<bool> mortar_zones;
    /** The load-balance test of the scene, for the pre-solve test and every MSA step. */
    std::unique_ptr<LoadBalanceTest> load_balance_test;
    HeldContactNodes                 held_nodes;
    /** The rows this rank holds of the dual vectors (set by hold()). */
    std::optional<LocalDualRows> dual_rows;
  };
} // namespace FetiContact
