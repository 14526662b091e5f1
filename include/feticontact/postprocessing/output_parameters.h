#pragma once

#include <deal.II/base/parameter_handler.h>

#include <feticontact/scene/parameter_file.h>

#include <string>

namespace FetiContact::Parameters
{
  /** `subsection Output`: what a run writes, and where. */
  struct Output
  {
    std::string directory              = "output";
    bool        write_vtu              = true;
    bool        write_displacement_csv = false;
    /** The discrete problem and solution in FCLIB's global form (fclib_problem.hdf5). */
    bool write_fclib = false;
    /**
     * The units of the FCLIB file: `nondimensional` divides lengths and displacements by a
     * length scale L and forces by a force scale S L² taken from the scene (doc/fclib.md), `SI`
     * writes metres and newtons.
     */
    enum class FclibUnits
    {
      nondimensional,
      SI
    };
    FclibUnits fclib_units = FclibUnits::nondimensional;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /**
   * `subsection Verification / subsection Hertz`: compare the contact of a body with a spherical
   * bottom on a rigid plane (contact zone 1) with Hertz's solution (doc/validation.md).
   */
  struct HertzComparison
  {
    bool enabled = false;
    /**
     * The total normal force P on the whole sphere; 0: the computed normal contact force times
     * the symmetry factor (for scenes loaded by a prescribed displacement).
     */
    double total_force = 0;
    /** The sphere's radius R; 0: the `Spherical bottom radius` of the zone's body. */
    double sphere_radius = 0;
    /** The whole sphere over the part meshed: 4 for a quarter model, 2 for a half, 1 for all. */
    double symmetry_factor = 1;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /** `subsection Verification`: checks against an independent solve. */
  struct Verification
  {
    /**
     * Assemble the undecomposed problem on the same mesh, solve it with CHOLMOD and report the
     * relative difference of the displacements (only for scenes without contact).
     */
    bool compare_with_monolithic = false;
    /**
     * A displacements.csv of an earlier run on the same mesh (for instance one solved to a much
     * tighter tolerance): report the differences from it in the maximum and in the energy norm
     * (summary.json: reference_difference). Empty: none.
     */
    std::string reference_displacements;
    /** Hertz's solution for the contact radius and peak pressure. */
    HertzComparison hertz;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    /**
     * Reads `subsection Verification`; a relative path of the reference displacements is taken
     * from the folder of the parameter file that names it (@p origins of this subsection).
     */
    void
    parse_parameters(dealii::ParameterHandler &prm, const EntryOrigins &origins);
  };
} // namespace FetiContact::Parameters
