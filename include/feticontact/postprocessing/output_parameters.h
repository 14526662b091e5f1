#pragma once

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace FetiContact::Parameters
{
  /** `subsection Output`: what a run writes, and where. */
  struct Output
  {
    std::string directory              = "output";
    bool        write_vtu              = true;
    bool        write_displacement_csv = false;

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

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };
} // namespace FetiContact::Parameters
