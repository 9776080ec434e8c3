#include "softflow/simulation/drop_run.hpp"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>

#include <fmt/format.h>

#include "softflow/analysis/theory/small_deformation.hpp"
#include "softflow/common/error.hpp"
#include "softflow/io/output_directory.hpp"
#include "softflow/io/vtu_writer.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/simulation/drop_simulation.hpp"

namespace softflow::simulation {

namespace {

using Clock = std::chrono::steady_clock;

std::string format_duration(double seconds) {
  const long s = std::lround(seconds);
  if (s >= 3600) return fmt::format("{}h{:02d}m", s / 3600, (s % 3600) / 60);
  if (s >= 60) return fmt::format("{}m{:02d}s", s / 60, s % 60);
  return fmt::format("{}s", s);
}

nlohmann::json theory_json(const io::CaseConfig& config) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t k = 0; k < config.objects.size(); ++k) {
    const auto& o = config.objects[k];
    if (!o.capillary_number && o.interfacial_tension <= 0) continue;
    const double ca = o.capillary_number ? *o.capillary_number
                                         : config.matrix_viscosity * config.shear_rate *
                                               io::mean_radius(o.geometry) / o.interfacial_tension;
    out.push_back({{"object", k + 1},
                   {"capillary_number", ca},
                   {"viscosity_ratio", o.viscosity_ratio},
                   {"taylor_D", analysis::theory::taylor_deformation(o.viscosity_ratio, ca)},
                   {"chaffey_brenner_theta_deg",
                    analysis::theory::chaffey_brenner_angle_deg(o.viscosity_ratio, ca)}});
  }
  return out;
}

// deformation.png through the repository's plotting script (matplotlib); a
// missing Python or matplotlib costs the plot, not the run.
void plot(const std::filesystem::path& directory) {
  const std::filesystem::path script =
      std::filesystem::path(SOFTFLOW_SOURCE_DIR) / "scripts" / "plot_timeseries.py";
  if (!std::filesystem::exists(script)) return;
  const std::string command = fmt::format("/usr/bin/python3 '{}' '{}' > /dev/null 2>&1",
                                          script.string(), directory.string());
  if (std::system(command.c_str()) != 0)
    fmt::print(stderr, "softflow: warning: could not draw deformation.png (needs python3-matplotlib)\n");
}

}  // namespace

nlohmann::json run_drop_case(const io::CaseConfig& config, const RunOptions& options,
                             MeshedCase meshed) {
  const auto start = Clock::now();
  const bool root = is_root();
  const std::filesystem::path directory =
      options.output_directory.value_or(std::filesystem::path(config.output_directory));
  std::unique_ptr<io::OutputDirectory> output;
  on_root_sharing_failure([&] { output = std::make_unique<io::OutputDirectory>(directory, true); });

  DropSimulation sim(config, std::move(meshed.mesh));
  // One ParaView time series: fields/*.vtu listed by fields.pvd.
  std::unique_ptr<io::FieldSeries> fields;
  if (root && config.write_fields)
    fields = std::make_unique<io::FieldSeries>(output->staging_path() / "fields",
                                               output->staging_path() / "fields.pvd");
  const int n_steps = static_cast<int>(std::lround(config.time.end / config.time.step));
  std::ofstream series;
  if (root) {
    series.open(output->path_of("timeseries.csv"));
    series << timeseries_header() << timeseries_rows(sim.initial_report()) << std::flush;
  }
  StepReport last = sim.initial_report();
  const double initial_volume = last.objects.empty() ? 0.0 : last.objects[0].volume;
  std::string stop_reason;
  StageSeconds total;
  int stokes_iterations = 0;
  try {
    for (int n = 0; n < n_steps; ++n) {
      last = sim.step();
      total.predict_and_translate += last.stages.predict_and_translate;
      total.ale += last.stages.ale;
      total.stokes_assembly += last.stages.stokes_assembly;
      total.stokes_solve += last.stages.stokes_solve;
      total.correct += last.stages.correct;
      total.analysis += last.stages.analysis;
      stokes_iterations += last.stokes_iterations;
      if (root) series << timeseries_rows(last) << std::flush;
      if (fields && config.time.fields_interval > 0 && last.step % config.time.fields_interval == 0)
        fields->write(sim.mesh(), sim.stokes().dofs(), sim.solution(), sim.time(), last.step);
      if (!options.quiet && root) {
        const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
        const auto& o = last.objects.front();
        fmt::print("step {:>6}/{}  t = {:8.4f}  D = {:.5f}  theta = {:6.2f} deg  dt = {:g}  "
                   "quality {:.3f}  ETA {}\n",
                   last.step, n_steps, last.time, o.deformation, o.theta_deg, config.time.step,
                   last.min_quality, format_duration(elapsed / last.step * (n_steps - last.step)));
      }
    }
  } catch (const Error& e) {
    stop_reason = e.what();
  }

  nlohmann::json summary = {
      {"softflow_version", SOFTFLOW_VERSION},
      {"case", config.name},
      {"status", stop_reason.empty() ? "completed" : "stopped"},
      {"mpi_ranks", la::mpi_size()},
      {"mesh", meshed.report},
      {"dimensionless_groups", io::to_json(io::dimensionless_groups(config))},
      {"unknowns", sim.stokes().dofs().n_dofs()},
      {"steps", sim.steps()},
      {"time", sim.time()},
      {"dt", config.time.step},
      {"theory", theory_json(config)},
      {"wall_seconds", std::chrono::duration<double>(Clock::now() - start).count()},
  };
  if (!stop_reason.empty()) summary["stop_reason"] = stop_reason;
  const double per_step = sim.steps() > 0 ? 1.0 / sim.steps() : 0.0;
  summary["seconds_per_step"] = {
      {"predict_and_translate", total.predict_and_translate * per_step},
      {"ale", total.ale * per_step},
      {"stokes_assembly", total.stokes_assembly * per_step},
      {"stokes_solve", total.stokes_solve * per_step},
      {"correct_interface", total.correct * per_step},
      {"analysis", total.analysis * per_step}};
  summary["stokes_iterations_per_step"] = stokes_iterations * per_step;
  summary["stokes_factorizations"] = sim.stokes().n_factorizations();
  nlohmann::json objects = nlohmann::json::array();
  for (const auto& o : last.objects)
    objects.push_back({{"object", o.object},
                       {"D", o.deformation},
                       {"theta_deg", o.theta_deg},
                       {"L", o.L},
                       {"B", o.B},
                       {"W", o.W},
                       {"ellipsoid_deviation", o.ellipsoid_deviation},
                       {"volume", o.volume},
                       {"volume_drift", o.object == 1 && initial_volume > 0
                                            ? o.volume / initial_volume - 1.0
                                            : 0.0}});
  summary["final"] = objects;

  on_root_sharing_failure([&] {
    output->write_text("case.toml", io::to_toml(config));
    const bool written = config.time.fields_interval > 0 && sim.steps() % config.time.fields_interval == 0;
    if (fields && sim.steps() > 0 && !written)
      fields->write(sim.mesh(), sim.stokes().dofs(), sim.solution(), sim.time(), sim.steps());
    output->write_text("summary.json", summary.dump(2) + "\n");
    series.close();
    plot(output->staging_path());
    output->commit();
  });
  if (!options.quiet && root) fmt::print("wrote {}\n", directory.string());
  if (!stop_reason.empty()) throw MeshError(stop_reason);
  return summary;
}

}  // namespace softflow::simulation
