#pragma once

#include <feticontact/postprocessing/hertz_comparison.h>
#include <feticontact/postprocessing/interface.h>

#include <optional>
#include <string>

/**
 * The postprocessors of a run, one class per evaluation or output (Postprocessing::create()
 * selects them).
 */
namespace FetiContact::Postprocessing
{
  /**
   * The constraints of the solution: the interface jump (summary.json: interface_jump) and the
   * displacements and multipliers that are not finite numbers (values_not_finite), which refute
   * the solution: overflow gives infinities and NaNs, which every later comparison would let
   * pass.
   */
  class ConstraintCheck : public Interface
  {
  public:
    std::string
    name() const override;
    void
    execute(const Input &input) override;
  };

  /**
   * The largest strain (summary.json: largest_strain), which refutes the solution above 0.1:
   * the program solves linear elasticity with contact about the initial geometry (small
   * strain), and larger strains (loads or moduli in other units) have no meaning there. It runs
   * after the contact conditions, whose penetration message names the strains too (note()), so
   * that a body pushed through its obstacle is reported as a penetration and a scene in other
   * units as outside small strain.
   */
  class SmallStrainCheck : public Interface
  {
  public:
    /** The largest strain that small-strain theory is taken to cover. */
    static constexpr double limit = 0.1;

    /** For another check's message: the strains if they exceed the limit, else "". */
    static std::string
    note(const Input &input);

    std::string
    name() const override;
    void
    execute(const Input &input) override;
  };

  /**
   * The contact conditions checked from the displacements and the forces (summary.json: kkt,
   * and the totals and states of the contact nodes, contact): a penetration into an obstacle
   * by more than 1 % of the largest displacement refutes the solution. With mortar zones also
   * the pointwise overlap of their surfaces (summary.json: mortar_overlap), which the weak
   * mortar constraint allows: a warning in the log above mortar_overlap_warning, no refutation.
   */
  class ContactConditions : public Interface
  {
  public:
    /** The overlap, relative to max |u|, above which the log warns. */
    static constexpr double mortar_overlap_warning = 0.05;

    std::string
    name() const override;
    void
    execute(const Input &input) override;

  private:
    /** summary.json's mortar_overlap, its line in the log and the warning. */
    static void
    report_mortar_overlap(const MortarOverlap &overlap, const Input &input);
  };

  /**
   * Verification/Hertz: the contact radius and the peak pressure against Hertz's solution
   * (compare_with_hertz(); summary.json: hertz). Runs before any postprocessor writes a file,
   * since a scene that does not fit the comparison is refused without result files. Skipped
   * when an earlier check (the penetration of ContactConditions) has refuted the solution.
   */
  class HertzComparison : public Interface
  {
  public:
    std::string
    name() const override;
    void
    execute(const Input &input) override;

    /** The comparison, after execute(). */
    const std::optional<HertzResult> &
    result() const
    {
      return hertz;
    }

  private:
    std::optional<HertzResult> hertz;
  };

  /**
   * The force balance of every body, applied + support + contact forces (summary.json:
   * equilibrium), and the independent checks of the equilibrium: a relative imbalance above
   * 1e-6 or an interface jump above 1e-2 refutes the solution.
   */
  class EquilibriumCheck : public Interface
  {
  public:
    std::string
    name() const override;
    void
    execute(const Input &input) override;
  };

  /**
   * Verification/Compare with monolithic solve: the relative difference of the displacements
   * from an undecomposed solve of every body (summary.json: monolithic_difference); skipped,
   * with a line in the log, for a scene with contact.
   */
  class MonolithicComparison : public Interface
  {
  public:
    std::string
    name() const override;
    void
    execute(const Input &input) override;
  };

  /**
   * Verification/Reference displacements: the differences from the displacements of an earlier
   * run, in the maximum and in the energy norm (summary.json: reference_difference).
   */
  class ReferenceComparison : public Interface
  {
  public:
    std::string
    name() const override;
    void
    execute(const Input &input) override;
  };

  /**
   * The contact nodes' results: contact.csv, and with Output/Write vtu the contact surfaces for
   * ParaView (contact_surface_NNNN.vtu, contact_surface.pvtu, contact_surface.pvd). Every rank
   * writes the nodes and the faces of its own subdomains (ContactOutputShare), rank 0 the
   * records.
   */
  class ContactOutput : public Interface
  {
  public:
    std::string
    name() const override;
    void
    execute(const Input &input) override;
  };

  /**
   * Output/Write FCLIB problem: the discrete contact problem and its solution in FCLIB's global
   * form (fclib_problem.hdf5), written by rank 0.
   */
  class FclibExport : public Interface
  {
  public:
    std::string
    name() const override;
    void
    execute(const Input &input) override;
  };

  /**
   * Output/Write vtu: the displacements and stresses of every subdomain for ParaView
   * (write_solution_vtu(); each rank writes its subdomains).
   */
  class SolutionOutput : public Interface
  {
  public:
    std::string
    name() const override;
    void
    execute(const Input &input) override;
  };

  /**
   * Output/Write displacement csv: displacements.csv, the position and the displacement of
   * every vertex of every body (body, x, y, z, ux, uy, uz), by body, subdomain and vertex
   * number: every rank writes the vertices whose lowest copy is in one of its subdomains, with
   * that copy's displacement, into the one file (ResultFiles::write_collectively()).
   */
  class DisplacementCsv : public Interface
  {
  public:
    std::string
    name() const override;
    void
    execute(const Input &input) override;
  };
} // namespace FetiContact::Postprocessing
