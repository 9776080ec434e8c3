// How a process started without an MPI launcher starts MPI.
#pragma once

#include <optional>

namespace softflow::parallel {

/// This process's rank as an MPI launcher (mpiexec, srun) exported it in
/// Open MPI's, PMIx's or PMI's variable, before MPI starts; none without a
/// launcher.
std::optional<int> launcher_rank();

/// Call before MPI_Init (PetscInitialize). A process started without a
/// launcher is an MPI singleton, and Open MPI's singleton start forks a
/// support daemon (orted) for dynamic process creation, which softflow
/// never uses (its sweeps start whole programs): 0.25 s of every serial
/// run's and every `check`'s start-up, measured. Asks Open MPI to start
/// isolated (ess_singleton_isolated) unless the user set that parameter;
/// under a launcher it changes nothing.
void start_singleton_without_daemon();

}  // namespace softflow::parallel
