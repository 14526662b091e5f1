#include <feticontact/base/mpi_start.h>

#include <array>
#include <cstdlib>

namespace FetiContact::MPIStart
{
  void
  prepare_singleton()
  {
    // Variables that Open MPI's, MPICH's, PMIx's and Slurm's launchers set in every process
    // they start.
    constexpr std::array<const char *, 6> launched_markers = {{"OMPI_COMM_WORLD_SIZE",
                                                               "PMIX_RANK",
                                                               "PMI_RANK",
                                                               "PMI_SIZE",
                                                               "SLURM_PROCID",
                                                               "MPI_LOCALRANKID"}};
    for (const char *marker : launched_markers)
      if (std::getenv(marker) != nullptr)
        return;
    // setenv with overwrite 0: a user's own choice stays.
    setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
    setenv("OMPI_MCA_pml", "ob1", 0);
    setenv("OMPI_MCA_btl", "self,vader", 0);
  }
} // namespace FetiContact::MPIStart
