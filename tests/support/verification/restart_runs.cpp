#include "support/verification/restart_runs.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <unistd.h>

#include "softflow/common/error.hpp"
#include "softflow/simulation/run_support.hpp"

namespace softflow::verification {

RestartRuns run_and_restart(const io::CaseConfig& config, int checkpoint_step, int steps,
                            const std::string& name) {
  const auto path = std::filesystem::temp_directory_path() /
                    fmt::format("softflow_{}_{}.h5", name, ::getpid());
  RestartRuns r;
  r.uninterrupted =
      std::make_unique<simulation::DropSimulation>(config, simulation::build_mesh(config).mesh);
  for (int n = 1; n <= steps; ++n) {
    r.last = r.uninterrupted->step();
    if (n == checkpoint_step) {
      r.uninterrupted->save(r.checkpoint);
      r.checkpoint.softflow_version = SOFTFLOW_VERSION;
      r.checkpoint.case_toml = io::to_toml(config);
      io::write_checkpoint(path, r.checkpoint);
    }
  }
  const auto saved = io::read_checkpoint(path);
  std::filesystem::remove(path);
  r.restarted = std::make_unique<simulation::DropSimulation>(config, saved.reference_mesh);
  r.restarted->restore(saved);
  for (int n = checkpoint_step + 1; n <= steps; ++n) r.again = r.restarted->step();
  return r;
}

std::vector<double> output_field_differences(const simulation::DropSimulation& a,
                                             const simulation::DropSimulation& b) {
  const auto fa = a.output_fields(), fb = b.output_fields();
  if (fa.size() != fb.size())
    throw Error(fmt::format("the two runs have {} and {} output fields", fa.size(), fb.size()));
  std::vector<double> out;
  for (std::size_t f = 0; f < fa.size(); ++f) {
    if (fa[f].values.size() != fb[f].values.size())
      throw Error(fmt::format("output field {} has {} and {} values", f, fa[f].values.size(),
                              fb[f].values.size()));
    double worst = 0.0;
    for (std::size_t i = 0; i < fa[f].values.size(); ++i)
      worst = std::max(worst, std::abs(fa[f].values[i] - fb[f].values[i]));
    out.push_back(worst);
  }
  return out;
}

}  // namespace softflow::verification
