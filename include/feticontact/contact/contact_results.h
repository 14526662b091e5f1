#pragma once

#include <deal.II/base/tensor.h>
#include <deal.II/lac/vector.h>

#include <feticontact/base/json_writer.h>
#include <feticontact/contact/contact_geometry.h>
#include <feticontact/contact/contact_rows.h>

#include <functional>
#include <mpi.h>
#include <optional>
#include <string>
#include <vector>

namespace FetiContact
{
  /** The state of a contact node after the solve. */
  enum class ContactStatus
  {
    open,  ///< no normal force
    stick, ///< pressed, ‖λ_T‖ < μ λ_N
    slip   ///< pressed, ‖λ_T‖ = μ λ_N
  };

  /** Name of a status for output: "open", "stick", "slip". */
  std::string
  to_string(const ContactStatus status);

  /**
   * Whether a contact node is pressed: its normal force above 1e-8 of the largest normal force
   * (@p largest_normal_force) of the contact problem and, where the gap after the load is known
   * (after the solve), at least as large relative to the largest normal force as the @p gap
   * relative to the largest displacement @p largest_displacement: of the two complementary
   * quantities λ_N and the gap, the one the solver left at its tolerance is the smaller (a node
   * with a gap of a tenth of the displacements and λ_N at 1e-7 of the largest is open). The rule
   * of the statuses exists only here and in contact_status(); the log, history.csv (without
   * the gap), contact.csv and the KKT check use it.
   */
  bool
  is_pressed(const double normal_force,
             const double largest_normal_force,
             const double gap                  = 0,
             const double largest_displacement = 1);

  /**
   * The status of a contact node: open unless @p pressed; slip when the norm of its
   * tangential force reaches its slip bound, ‖λ_T‖ ≥ (1 − 1e-4) g − @p slack (a frictionless
   * pressed node, g = 0, slips); stick otherwise.
   */
  ContactStatus
  contact_status(const bool   pressed,
                 const double tangential_force,
                 const double slip_bound,
                 const double slack = 0);

  /**
   * Forces and kinematics of one contact node, computed from the multipliers λ and the
   * displacements u: normal force λ_N ≥ 0 (pushing the slave body away from the obstacle),
   * tangential force (λ_T1, λ_T2) in the frame {t1, t2}, the current gap d − N u, the slip
   * (T1 u, T2 u) (relative tangential displacement) and the status.
   */
  struct ContactNodeResult
  {
    double        lambda_N = 0;
    double        lambda_T[2]{0, 0};
    double        gap = 0;
    double        slip[2]{0, 0};
    ContactStatus status = ContactStatus::open;
  };

  /**
   * The pointwise overlap of the two surfaces of the mortar zones after the load, relative to
   * max |u|: the deepest slave vertex behind the deformed master surface and the deepest master
   * vertex behind the deformed slave surface (each: its depth behind a triangle whose normal
   * projection it lies in). Mortar rows hold the gap weakly, ∫ ψ_k g ≥ 0 for each slave node, so
   * the surfaces may overlap between and around the nodes, most at the edge of the contact
   * region; the overlap falls with h (doc/contact.md, "Non-matching meshes").
   */
  struct MortarOverlap
  {
    double slave_into_master = 0;
    double master_into_slave = 0;

    /** The larger of the two. */
    double
    largest() const;

    /** The two values as a JSON object for summary.json. */
    JsonObject
    json() const;
  };

  /**
   * The independent check of a contact solution (the KKT check of summary.json), from u and the
   * contact forces, all relative: largest penetration (max(N u − d)⁺ / max |u|), largest violation
   * of ‖λ_T‖ ≤ μ λ_N (/ max μ λ_N), normal complementarity (max |λ_N (d − N u)| / (max λ_N max
   * |u|)), and for slipping nodes the largest angle between λ_T and the slip (radians), plus
   * totals.
   */
  struct ContactCheck
  {
    double penetration     = 0;
    double cone_violation  = 0;
    double complementarity = 0;
    double slip_angle      = 0;
    double negative_normal = 0; ///< max (−λ_N)⁺ / max λ_N
    /** Largest relative tangential displacement ‖T u‖ of a pressed node, / max |u|. */
    double               pressed_slip = 0;
    dealii::Tensor<1, 3> normal_force, tangential_force;
    unsigned int         n_open = 0, n_stick = 0, n_slip = 0;
    /** The overlap of the surfaces of the mortar zones (none: the scene has no mortar zone). */
    std::optional<MortarOverlap> mortar_overlap;

    /** The check as a JSON object for summary.json. */
    JsonObject
    json() const;
  };

  /**
   * The penetration of the bodies into the rigid-plane obstacles, from the displacements alone:
   * max over the zones z and the vertices x of (−(x + u(x) − p_z)·n_z)⁺, relative to max |u|,
   * for every vertex of zone z's surface (@p triangles); and for every other vertex of a body
   * that lies in front of all the body's rigid planes before the load, the least of its depths
   * behind them (inside all of them: several planes may form one convex obstacle). It counts
   * also the vertices that are no contact nodes of the zone, those that are contact nodes of
   * another zone (a node on the edge of two obstacles is checked against both), and those off
   * the surface that a surface chosen too small lets through the obstacle. Spheres and cylinders
   * the same way, each for itself. Body pairs: every vertex of the slave surface that is no
   * contact node of the zone (beyond the search distance) against the deformed master surface,
   * its depth behind a master triangle it projects into (up to 2 max |u| plus
   * @p largest_cell, the largest cell diameter of the bodies).
   *
   * This function checks the vertices of the zones' surfaces (@p surfaces, displaced by @p u,
   * which holds the displacements of their vertices), the largest over all ranks of @p comm,
   * each rank the triangles and uncoupled vertices it lists; a rank gets the deformed master
   * triangles near its uncoupled vertices from the ranks that list them. The vertices off the
   * surfaces are checked one by one by vertex_penetration(), whose largest value over all
   * vertices, divided by @p u_max (max |u|), completes the check. Collective.
   */
  double
  surface_penetration(const Parameters::Contact &contact,
                      const ContactSurfaces     &surfaces,
                      const VertexDisplacements &u,
                      const double               u_max,
                      const double               largest_cell,
                      const MPI_Comm             comm);

  /**
   * The overlap (MortarOverlap) of the zones z with @p mortar_zones[z] (mortar rows), from the
   * deformed positions of the vertices and triangles of their surfaces (@p surfaces, displaced by
   * @p u), up to 2 @p u_max + @p largest_cell deep, the largest over all ranks of @p comm: each
   * rank measures the vertices it lists against the triangles near them, which the ranks that
   * list them send it (the exchange of surface_penetration()). Collective.
   */
  MortarOverlap
  mortar_overlap(const std::vector<bool>   &mortar_zones,
                 const ContactSurfaces     &surfaces,
                 const VertexDisplacements &u,
                 const double               u_max,
                 const double               largest_cell,
                 const MPI_Comm             comm);

  /**
   * The part of the check of surface_penetration() for one vertex @p x of body @p body,
   * displaced by @p u, wherever it lies: its depth inside a sphere or cylinder of the body's
   * zones that it starts outside of, and, if it starts in front of all the body's rigid planes,
   * the least of its depths behind them (not relative).
   */
  double
  vertex_penetration(const Parameters::Contact  &contact,
                     const unsigned int          body,
                     const dealii::Point<3>     &x,
                     const dealii::Tensor<1, 3> &u);

  /**
   * Evaluates every contact node of @p nodes. @p u: the displacements of the nodes' vertices,
   * @p u_max the largest displacement of the bodies; @p lambda: the multiplier of a row in the
   * layout of @p layout (disc form: two tangential multipliers; polygonal: s multipliers whose
   * force is Σ λ_j d_j). The nodes are those of this rank and @p check is that of the nodes of
   * all ranks of @p comm, each node on one rank (hold_contact_nodes()); with MPI_COMM_SELF,
   * @p nodes are all nodes. Status: open if λ_N ≤ 1e-8 max λ_N, slip if ‖λ_T‖ ≥ (1 − 1e-4) μ λ_N
   * (a margin well above the MSA tolerance, which leaves λ_T on the previous slip bound),
   * else stick. With a @p tresca_slip_bound (Tresca friction) the bound of nodes with μ > 0 is
   * that given slip bound g instead of μ λ_N (Coulomb friction, no value).
   */
  std::vector<ContactNodeResult>
  evaluate_contact(const std::vector<ContactNode>                  &nodes,
                   const DualLayout                                &layout,
                   const std::function<double(const unsigned int)> &lambda,
                   const VertexDisplacements                       &u,
                   const double                                     u_max,
                   ContactCheck                                    &check,
                   const std::optional<double>                      tresca_slip_bound,
                   const MPI_Comm                                   comm);

  /**
   * Writes the rows of contact.csv for the nodes @p which (indices into @p nodes, in that order),
   * after the header line if @p header: zone, body, x, y, z, λ_N, λ_T1, λ_T2, gap, slip_1,
   * slip_2, status, the lumped area, the pressure λ_N / D_kk, the weighted initial gap
   * g̃_k = D_kk d_k and D_kk per node (D_kk: the dual-basis area of a mortar node, the lumped area
   * otherwise).
   */
  void
  write_contact_csv(std::ostream                         &out,
                    const std::vector<ContactNode>       &nodes,
                    const std::vector<ContactNodeResult> &results,
                    const std::vector<unsigned int>      &which,
                    const bool                            header);
} // namespace FetiContact
