// Remeshes the state of a run's checkpoint once and reports it: for
// measuring a remesh on a real deformed state (docs/remeshing.md).
//
//   remesh_checkpoint OUTDIR
//
// Reads OUTDIR/case.toml and OUTDIR/checkpoint.h5, restores the run, calls
// DropSimulation::remesh and prints one JSON line (nodes, worst quality
// before and after, volume change, extrapolation, seconds), or the error.
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>
#include <petscsys.h>

#include "softflow/common/error.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/io/checkpoint.hpp"
#include "softflow/simulation/drop_simulation.hpp"

using namespace softflow;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: remesh_checkpoint OUTDIR\n");
    return 1;
  }
  const std::filesystem::path directory = argv[1];
  int petsc_argc = 1;
  if (PetscInitialize(&petsc_argc, &argv, nullptr, nullptr) != 0) return 1;
  int status = 0;
  try {
    const auto config = io::read_case_file(directory / "case.toml");
    const auto checkpoint = io::read_checkpoint(directory / "checkpoint.h5");
    simulation::DropSimulation sim(config, checkpoint.reference_mesh);
    sim.restore(checkpoint);
    const auto e = sim.remesh("remesh_checkpoint");
    fmt::print(
        "{{\"step\": {}, \"t\": {}, \"nodes_before\": {}, \"nodes_after\": {}, \"quality_before\": {:.4f}, "
        "\"quality_after\": {:.4f}, \"volume_change\": {:.2e}, \"extrapolation\": {:.2e}, \"seconds\": {:.2f}}}\n",
        e.step, e.time, e.nodes_before, e.nodes_after, e.quality_before, e.quality_after, e.volume_change,
        e.extrapolation, e.seconds);
  } catch (const Error& e) {
    std::fprintf(stderr, "remesh_checkpoint: %s\n", e.what());
    status = 2;
  }
  PetscFinalize();
  return status;
}
