#pragma once

namespace FetiContact::MPIStart
{
  /**
   * Prepares Open MPI for a process that no launcher (mpirun, mpiexec, srun) started: a
   * singleton, MPI_COMM_WORLD of size one.
   *
   * By default Open MPI starts a singleton as if it could later spawn or join other processes:
   * it forks a runtime daemon and probes every network transport, which takes about 0.4 s
   * before the first line of the program runs. A singleton of this program never spawns and
   * talks only to itself, so this function asks for an isolated singleton with the shared-memory
   * and self transports (the environment variables OMPI_MCA_ess_singleton_isolated,
   * OMPI_MCA_pml and OMPI_MCA_btl); MPI_Init then takes a few hundredths of a second. Variables
   * that the user set are left as they are, and nothing is changed in a process that a launcher
   * started (its rank variables are set). Must be called before MPI is initialized.
   */
  void
  prepare_singleton();
} // namespace FetiContact::MPIStart
