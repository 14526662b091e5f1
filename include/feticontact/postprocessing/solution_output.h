#pragma once

#include <deal.II/fe/mapping.h>
#include <deal.II/lac/vector.h>

#include <feticontact/base/output_files.h>
#include <feticontact/subdomain/subdomain.h>

#include <mpi.h>
#include <string>
#include <vector>

namespace FetiContact
{
  /**
   * Writes the solution for ParaView: one `solution_NNNN.vtu` per subdomain (written by the rank
   * that owns it) with the displacement, the stress tensor, the von Mises stress, the
   * subdomain id and the body id (the last three as cell data), and on rank 0 `solution.pvtu`
   * listing them and `solution.pvd` (one time step) pointing to it, into @p directory through
   * @p files (this rank's result files).
   */
  void
  write_solution_vtu(ResultFiles                               &files,
                     const MPI_Comm                             comm,
                     const std::vector<Subdomain *>            &owned,
                     const std::vector<dealii::Vector<double>> &u,
                     const unsigned int                         n_subdomains,
                     const dealii::Mapping<3>                  &mapping,
                     const std::string                         &directory);
} // namespace FetiContact
