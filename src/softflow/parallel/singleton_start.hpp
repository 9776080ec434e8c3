// How a process started without an MPI launcher starts MPI.
#pragma once

#include <optional>

namespace softflow::parallel {

/// This process's rank as an MPI launcher (mpiexec, srun) exported it in
/// Open MPI's, PMIx's or PMI's variable, before MPI starts; none without a
/// launcher; -1 for a value that is no rank (never taken for rank 0).
std::optional<int> launcher_rank();

/// Call before MPI_Init (PetscInitialize). A process started without a
/// launcher is an MPI singleton, and Open MPI's singleton start forks a
/// support daemon (orted) for dynamic process creation, which softflow
/// never uses (its sweeps start whole programs): 0.25 s of the start-up of
/// every serial command that starts MPI (run, response, a check with PETSc
/// options), measured. Asks Open MPI to start
/// isolated (ess_singleton_isolated) unless the user set that parameter;
/// under a launcher it changes nothing.
void start_singleton_without_daemon();

}  // namespace softflow::parallel
