#pragma once

#include <deal.II/base/convergence_table.h>

#include <feticontact/base/output_files.h>
#include <feticontact/scene/scene_parameters.h>

#include <mpi.h>
#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * A mesh refinement study (`subsection Refinement study`): the scene of one parameter file
   * solved once per entry of `Subdivision factors`, each time with the Subdivisions of every box
   * body multiplied by the factor, into Output/Directory/cycle-N (a complete run each: log.txt,
   * summary.json, ParaView files). The results go into a deal.II ConvergenceTable, printed and
   * written to Output/Directory as convergence_table.txt (aligned text), convergence_table.org
   * (org-mode, also valid Markdown) and refinement_study.json (one array per column):
   * factor, unknowns, contact nodes, h_min (the smallest cell diameter), MSA iterations, Hessian
   * multiplications, solve time, and with Verification/Hertz the measured a and p0, their
   * relative errors and the rates of those errors, log(e_{i−1}/e_i) / log(f_i/f_{i−1}) for the
   * factors f: every cell's size scales as 1/f, since grading and a spherical bottom are fixed
   * maps of the box that the factor refines uniformly.
   */
  class RefinementStudy
  {
  public:
    /** The parameter file, the --set overrides and the file's text (for input.prm). */
    RefinementStudy(const MPI_Comm                  comm,
                    const std::string              &filename,
                    const std::vector<std::string> &overrides,
                    const std::string              &input);

    /**
     * Runs every cycle; returns false (after writing the table of the cycles done) as soon as
     * one does not converge; then message() says which.
     */
    bool
    run();

    const std::string &
    message() const
    {
      return failure;
    }

  private:
    MPI_Comm                       comm;
    const std::string              filename;
    const std::vector<std::string> overrides;
    const std::string              input;
    std::string                    failure;

    /** One cycle: its scene, the parameters as read, its subdivisions and output folder. */
    struct Cycle
    {
      Parameters::Scene scene;
      std::string       effective_parameters, subdivisions, directory;
    };

    /** The scene of cycle @p cycle: @p base with every body's Subdivisions times its factor. */
    Cycle
    make_cycle(const Parameters::Scene &base, unsigned int cycle) const;

    /** Writes the table files into @p directory (rank 0). */
    void
    write_table(dealii::ConvergenceTable &table,
                ResultFiles              &files,
                const std::string        &directory) const;
  };
} // namespace FetiContact
