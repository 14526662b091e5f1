#pragma once

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/tensor.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/vector.h>

#include <feticontact/base/output_files.h>
#include <feticontact/contact/contact_forces.h>
#include <feticontact/contact/contact_geometry.h>
#include <feticontact/contact/contact_results.h>
#include <feticontact/contact/contact_rows.h>
#include <feticontact/core/summary.h>
#include <feticontact/scene/body.h>
#include <feticontact/scene/scene_parameters.h>
#include <feticontact/subdomain/subdomain.h>

#include <functional>
#include <memory>
#include <mpi.h>
#include <optional>
#include <string>
#include <vector>

namespace FetiContact::Postprocessing
{
  /**
   * What a postprocessor sees of a solved run: read access to the scene, its bodies and this
   * rank's subdomains, the displacements (per subdomain and gathered per body vertex), the
   * multipliers, the evaluated contact nodes; and the places a postprocessor writes to: this
   * rank's result files, the summary under construction and the log.
   */
  struct Input
  {
    MPI_Comm                                  comm;
    const Parameters::Scene                  &parameters;
    const std::vector<std::unique_ptr<Body>> &bodies;
    /** The number of the first subdomain of each body, and the total at the end. */
    const std::vector<unsigned int> &first_subdomain;
    /** The rank of every subdomain. */
    const std::vector<unsigned int> &subdomain_owner;
    /** This rank's subdomains and their displacements (by the subdomains' DoFs). */
    const std::vector<Subdomain *>            &owned;
    const std::vector<dealii::Vector<double>> &u;
    /**
     * The number of entries of all of λ and of the displacements of all vertices that are not
     * finite numbers; and max |u| over all vertices.
     */
    unsigned int lambda_not_finite, u_not_finite;
    double       u_max;
    /**
     * max |B_E u − c| over the equality rows (the jump across the subdomain interfaces and, with
     * TFETI, the Dirichlet misfit), relative to u_max.
     */
    double interface_jump;
    /**
     * The largest absolute principal strain of any cell of any subdomain (0 when some value is
     * not finite).
     */
    double largest_strain;
    /**
     * The contact nodes of this rank, with their rows (hold_contact_nodes()): each node on one
     * rank of comm, that of its home subdomain (the lowest copy of its slave vertex).
     */
    const std::vector<ContactNode> &contact_nodes;
    const DualLayout               &contact_layout;
    const ContactSurfaces          &contact_surfaces;
    /** Per contact node (of contact_nodes): the forces, the gap, the slip and the status. */
    const std::vector<ContactNodeResult> &contact_results;
    /** The contact conditions checked from u and the forces (the penetration of every vertex). */
    const ContactCheck &contact_check;
    /** The forces of the contacts on each body and the resultant of each zone. */
    const ContactForces &contact_forces;
    /** Verification/Reference displacements, by body and vertex (empty: none). */
    const std::optional<VertexDisplacements> &reference_displacements;
    const dealii::Mapping<3>                 &mapping;
    const dealii::FiniteElement<3>           &fe;
    const std::string                        &output_directory;
    ResultFiles                              &result_files;
    Summary                                  &summary;
    const dealii::ConditionalOStream         &pcout;

    /** Whether this is rank 0, which writes the files of the whole scene. */
    bool
    root() const;

    /**
     * Runs @p write on this rank and makes an OutputError of any rank every rank's, so that all
     * ranks stop together. Collective.
     */
    void
    on_all_ranks(const std::function<void()> &write) const;

    /**
     * Summary::check(), and the message in the log when the check refutes the solution.
     */
    void
    check(const std::string &key,
          const std::string &description,
          const double       value,
          const double       limit) const;
  };

  /**
   * A postprocessor: one evaluation or output of a solved run (ASPECT's
   * Postprocess::Interface). execute() is called on every rank, in the order of the list
   * create() makes; it may be collective.
   */
  class Interface
  {
  public:
    virtual ~Interface() = default;

    /** What the postprocessor does, for messages. */
    virtual std::string
    name() const = 0;

    /** Evaluates or writes; results for summary.json go into @p input.summary. */
    virtual void
    execute(const Input &input) = 0;
  };

  /**
   * The postprocessors the parameter file selects, in the order they run: first the checks and
   * comparisons, which may refuse the scene (Verification/Hertz) or the solution, then the
   * files. Always: the constraint check and the force balance; with contact nodes the contact
   * check and the contact output (contact.csv, and the contact surface VTU with Output/Write vtu);
   * Verification/Hertz, Verification/Compare with monolithic solve, Verification/Reference
   * displacements, Output/Write FCLIB problem, Output/Write vtu and Output/Write displacement
   * csv each add theirs.
   */
  std::vector<std::unique_ptr<Interface>>
  create(const Parameters::Scene &parameters, const bool has_contact);
} // namespace FetiContact::Postprocessing
