#include <feticontact/base/input_parsing.h>
#include <feticontact/postprocessing/output_parameters.h>

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
                      "(summary.json: monolithic_difference).");
    prm.declare_entry("Reference displacements",
                      "",
                      Patterns::Anything(),
                      "A displacements.csv written by an earlier run on the same mesh (Output/"
                      "Write displacement csv), e.g. one solved to a tighter tolerance: report "
                      "the relative difference of the displacements from it, in the maximum "
                      "norm and in the energy norm of the body's stiffness (summary.json: "
                      "reference_difference). Empty: no comparison.");
    prm.leave_subsection();
  }

  void
  Verification::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Verification");
    compare_with_monolithic = prm.get_bool("Compare with monolithic solve");
    reference_displacements = InputParsing::trim(prm.get("Reference displacements"));
    require(reference_displacements.empty() || std::ifstream(reference_displacements).good(),
            "Verification/Reference displacements: cannot open '" + reference_displacements + "'.");
    prm.leave_subsection();
  }
} // namespace FetiContact::Parameters
