// `softflow moduli`: the linear viscoelastic moduli of an emulsion as a sweep over random
// configurations (and frequencies, volume fractions, ...), with Oldroyd's theory beside
// every point (thesis ch. 4, Figs. 4.11-4.20; issue 32 item 4).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "softflow/io/sweep_case.hpp"
#include "softflow/simulation/sweep.hpp"

namespace softflow::simulation {

/// One point of a moduli study: the cases that differ only in emulsion.seed.
struct ModuliPoint {
  std::vector<std::string> labels;  ///< the other parameters' values, as in sweep labels
  std::vector<std::string> cases;   ///< the seeds' run labels
  int fitted = 0;                   ///< configurations with moduli (completed runs)
  double phi = 0.0;                 ///< mean volume fraction in the cube
  double storage_mean = 0.0, storage_std = 0.0;  ///< G' R / Gamma
  double loss_mean = 0.0, loss_std = 0.0;        ///< G'' / (eta_m omega)
  double worst_residual = 0.0;                   ///< largest fit residual of sigma_xy
  double omega_star = 0.0;
  double oldroyd_storage = 0.0, oldroyd_loss = 0.0;  ///< at the mean phi
};

/// The points of `sweep` from its cases' summary.json "moduli" (in
/// `directory`): grouped by every parameter but emulsion.seed, mean and
/// sample standard deviation over the configurations (0 for one), Oldroyd's
/// moduli (analysis::theory::oldroyd_moduli) at the group's mean volume
/// fraction, objects[1]'s lambda and slip, and omega* = omega eta_m R / Gamma.
std::vector<ModuliPoint> collect_moduli(const io::Sweep& sweep, const std::filesystem::path& directory);

/// `softflow moduli CASE.toml`: the case (oscillatory flow, [bulk_stress], Newtonian drops,
/// usually [emulsion] with seed = [1, 2, 3, 4, 5] and a list of frequencies or volume
/// fractions) runs as `softflow sweep` runs it (resumable, N at a time), then
/// moduli.md, moduli.csv, moduli.png in its output directory: one row per point
/// with mean and standard deviation of G', G'' and Oldroyd's beside them.
/// InputError before anything runs for a case that cannot give moduli (steady
/// flow, no bulk_stress.box_side, an elastic or viscoelastic object).
/// Returns the sweep's exit code.
int run_moduli_study(const std::filesystem::path& case_file, const SweepOptions& options);

}  // namespace softflow::simulation
