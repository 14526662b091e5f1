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

    /** Declares everything for a scene with @p n_bodies bodies and @p n_zones contact zones. */
    static void
    declare_parameters(dealii::ParameterHandler &prm,
                       const unsigned int        n_bodies,
                       const unsigned int        n_zones = 0);
    void
    parse_parameters(dealii::ParameterHandler &prm, const std::string &base_directory);

    /**
     * Reads @p filename into @p prm: first `Number of bodies` and `Contact/Number of zones`
     * alone, then everything with that many body and zone subsections declared. Throws InputError
     * naming the line for malformed input, unknown entries and values that do not match their
     * pattern.
     *
     * @p overrides ("Body 1/Mesh/Subdivisions=24, 8, 8", from the command line option --set)
     * are applied after the file, as if appended to it.
     */
    static void
    read_parameter_file(dealii::ParameterHandler       &prm,
                        const std::string              &filename,
                        const std::vector<std::string> &overrides = {});
  };
} // namespace FetiContact::Parameters
