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

    static void
    declare_parameters(dealii::ParameterHandler &prm);
    void
    parse_parameters(dealii::ParameterHandler &prm);
  };
} // namespace FetiContact::Parameters
