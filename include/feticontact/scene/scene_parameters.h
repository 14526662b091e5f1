#pragma once

#include <deal.II/base/parameter_handler.h>

#include <feticontact/contact/contact_solver_parameters.h>
#include <feticontact/feti/feti_parameters.h>
#include <feticontact/postprocessing/output_parameters.h>
#include <feticontact/scene/body_parameters.h>
#include <feticontact/scene/contact_parameters.h>

#include <string>
#include <vector>

namespace FetiContact::Parameters
{
  /**
   * `subsection Refinement study`: solve the scene on a sequence of meshes, each generated box
   * mesh with its `Subdivisions` multiplied by a factor (the decomposition, grading and every
   * other entry kept), and tabulate the results with their convergence rates (RefinementStudy).
   */
  struct RefinementStudy
  {
    /** The factors, one solve each, in the given order (increasing); empty: a single run. */
    std::vector<double> subdivision_factors;

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };

  /**
   * The whole parameter file: the bodies (`subsection Body 1`, `Body 2`, …, as many as
   * `Number of bodies`), the FETI solver, output and verification.
   */
  struct Scene
  {
    std::vector<Body> bodies;
    Contact           contact;
    ContactSolver     contact_solver;
    Feti              feti;
    Output            output;
    Verification      verification;
    RefinementStudy   refinement_study;

    /** Declares everything for a scene with @p n_bodies bodies and @p n_zones contact zones. */
    static void
    declare_parameters(dealii::ParameterHandler &prm,
                       const unsigned int        n_bodies,
                       const unsigned int        n_zones = 0);
    /**
     * Reads the scene from @p prm; file names in entries are found next to the parameter file
     * that set them (@p origins, from read_parameter_file()).
     */
    void
    parse_parameters(dealii::ParameterHandler &prm, const EntryOrigins &origins = {});

    /**
     * Reads @p filename into @p prm: first `Number of bodies` and `Contact/Number of zones`
     * alone, then everything with that many body and zone subsections declared. Throws InputError
     * naming the line for malformed input, unknown entries and values that do not match their
     * pattern.
     *
     * @p overrides ("Body 1/Mesh/Subdivisions=24, 8, 8", from the command line option --set)
     * are applied after the file, as if appended to it. `include` lines are expanded first
     * (ParameterFileText); its warnings (an entry set twice in one subsection of one file) are
     * appended to @p warnings if given. Every body and zone that the counts announce must have
     * its subsection. Returns where each entry was set.
     */
    static EntryOrigins
    read_parameter_file(dealii::ParameterHandler       &prm,
                        const std::string              &filename,
                        const std::vector<std::string> &overrides = {},
                        std::vector<std::string>       *warnings  = nullptr);

    /**
     * The output directory that @p filename with @p overrides names (Output/Directory, or its
     * default), found by a lenient scan that works also when the file fails to parse; empty if
     * the file cannot be read.
     */
    static std::string
    output_directory(const std::string &filename, const std::vector<std::string> &overrides);
  };
} // namespace FetiContact::Parameters
