#include <feticontact/base/input_parsing.h>
#include <feticontact/postprocessing/fclib_export.h>
#include <feticontact/postprocessing/output_parameters.h>

#include <filesystem>
#include <fstream>

namespace FetiContact::Parameters
{
  using namespace dealii;

  void
  Output::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Output");
    prm.declare_entry("Directory",
                      "output",
                      Patterns::Anything(),
                      "Folder for all output (created if missing; relative to the current "
                      "working directory).");
    prm.declare_entry("Write vtu",
                      "true",
                      Patterns::Bool(),
                      "Write the solution for ParaView: solution.pvd → solution.pvtu → one "
                      ".vtu per subdomain (displacement, stress, von Mises stress, subdomain "
                      "and body id).");
    prm.declare_entry("Write displacement csv",
                      "false",
                      Patterns::Bool(),
                      "Write displacements.csv: body, x, y, z, ux, uy, uz for every mesh vertex.");
    prm.declare_entry("Write FCLIB problem",
                      "false",
                      Patterns::Bool(),
                      "Write the discrete contact problem and the computed solution to "
                      "fclib_problem.hdf5 in the global form of the Frictional Contact Library "
                      "(FCLIB): M the stiffness of the undecomposed bodies without prescribed "
                      "DoFs, H the contact frames [normal, t1, t2], w the gaps, mu per contact "
                      "(doc/fclib.md), for Siconos or any other FCLIB solver. Coulomb friction "
                      "only.");
    prm.declare_entry("FCLIB units",
                      "nondimensional",
                      Patterns::Selection("nondimensional|SI"),
                      "The units of fclib_problem.hdf5. 'nondimensional': lengths and "
                      "displacements (v, u, w) are divided by a length scale L, forces (r, f) by "
                      "a force scale S L² and M by S L; H and mu are unchanged, so the stored "
                      "problem holds exactly when the SI one does. S L = E_max h_c (E_max the "
                      "largest Young's modulus, h_c the square root of the slave contact area "
                      "per contact node) makes M of order one, S L² = max(max |f|, E_max h_c "
                      "max |w|) the load, so that f, r, u and v are of order one too and FCLIB "
                      "solvers' default tolerances apply (doc/fclib.md). The file stores L, S "
                      "and S L² (root attributes length_scale, stress_scale, force_scale; "
                      "attribute units) and a line in the problem's description. 'SI': metres "
                      "and newtons, the scales stored as 1.");
    prm.leave_subsection();
  }

  void
  Output::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Output");
    directory = InputParsing::trim(prm.get("Directory"));
    require(!directory.empty(), "Output/Directory must not be empty.");
    write_vtu              = prm.get_bool("Write vtu");
    write_displacement_csv = prm.get_bool("Write displacement csv");
    write_fclib            = prm.get_bool("Write FCLIB problem");
    fclib_units = prm.get("FCLIB units") == "SI" ? FclibUnits::SI : FclibUnits::nondimensional;
    require(!write_fclib || fclib_available(),
            "Output/Write FCLIB problem: this build has no FCLIB (install libfclib-dev, then run "
            "cmake again).");
    prm.leave_subsection();
  }

  void
  Verification::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Verification");
    prm.declare_entry("Compare with monolithic solve",
                      "false",
                      Patterns::Bool(),
                      "Also solve the undecomposed problem on the same mesh with a sparse "
                      "direct solver and report the relative difference of the displacements "
                      "(summary.json: monolithic_difference). It costs one factorization of the "
                      "whole body (CHOLMOD, 64-bit): on the brick at 10⁶ unknowns 22 GB of "
                      "memory and about 7 minutes (doc/performance.md).");
    prm.declare_entry("Reference displacements",
                      "",
                      Patterns::Anything(),
                      "A displacements.csv written by an earlier run on the same mesh (Output/"
                      "Write displacement csv), e.g. one solved to a tighter tolerance: report "
                      "the relative difference of the displacements from it, in the maximum "
                      "norm and in the energy norm of the body's stiffness (summary.json: "
                      "reference_difference). Empty: no comparison.");
    HertzComparison::declare_parameters(prm);
    prm.leave_subsection();
  }

  void
  Verification::parse_parameters(ParameterHandler &prm, const EntryOrigins &origins)
  {
    prm.enter_subsection("Verification");
    compare_with_monolithic = prm.get_bool("Compare with monolithic solve");
    const std::string given = InputParsing::trim(prm.get("Reference displacements"));
    reference_displacements = origins.resolve("Reference displacements", given);
    std::error_code   error;
    const std::string tried =
      std::filesystem::absolute(reference_displacements, error).lexically_normal().string();
    require(reference_displacements.empty() || std::ifstream(reference_displacements).good(),
            "Verification/Reference displacements: cannot open '" + given + "'" +
              origins.where("Reference displacements") + ": looked for <" + tried + ">.");
    hertz.parse_parameters(prm);
    prm.leave_subsection();
  }

  void
  HertzComparison::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Hertz");
    prm.declare_entry("Enabled",
                      "false",
                      Patterns::Bool(),
                      "Compare the contact of zone 1 (a body with a spherical bottom on a rigid "
                      "plane or on another body's flat face, or a body under a rigid sphere) "
                      "with Hertz's solution a = (3PR/(4E*))^(1/3), p0 = 3P/(2πa²), "
                      "1/E* = (1 − ν₁²)/E₁ (+ (1 − ν₂²)/E₂ of the master body): the contact "
                      "radius and the peak pressure fitted to the nodal pressures λ_N / D_kk "
                      "of the whole contact zone, p² = p0²(1 − r²/a²) by least squares in r² "
                      "(log.txt, summary.json: hertz).");
    prm.declare_entry("Total force",
                      "0",
                      Patterns::Double(0),
                      "P: the total normal force on the whole sphere [N]; 0: the computed normal "
                      "contact force times the symmetry factor (scenes loaded by a prescribed "
                      "displacement).");
    prm.declare_entry("Sphere radius",
                      "0",
                      Patterns::Double(0),
                      "R [m]; 0: the Spherical bottom radius of the zone's body.");
    prm.declare_entry("Symmetry factor",
                      "1",
                      Patterns::Double(1),
                      "The whole sphere over the part meshed: 4 for a quarter model (two symmetry "
                      "planes), 2 for a half model, 1 for the whole body.");
    prm.leave_subsection();
  }

  void
  HertzComparison::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Hertz");
    enabled         = prm.get_bool("Enabled");
    total_force     = prm.get_double("Total force");
    sphere_radius   = prm.get_double("Sphere radius");
    symmetry_factor = prm.get_double("Symmetry factor");
    prm.leave_subsection();
  }
} // namespace FetiContact::Parameters
