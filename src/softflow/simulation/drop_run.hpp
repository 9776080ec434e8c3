// A drop-in-shear run in time: the loop, its progress line, time series, summary and plot.
#pragma once

#include <nlohmann/json.hpp>

#include "softflow/io/case_config.hpp"
#include "softflow/simulation/run_support.hpp"
#include "softflow/simulation/stokes_run.hpp"

namespace softflow::simulation {

/// Runs `config` from t = 0 to time.end with the thesis's Steps 1-5
/// (DropSimulation) and writes into the output directory: case.toml,
/// timeseries.csv (one row per object and step), fields.pvd (final state, and
/// every time.fields_interval steps), summary.json (final D and theta, theory,
/// wall time, unknowns, steps, volume drift) and deformation.png (D(t), theta(t)
/// beside Taylor and Chaffey-Brenner). If the run stops early (a degraded mesh,
/// a solver failure), what was computed is still written, the summary says why,
/// and the error is rethrown.
nlohmann::json run_drop_case(const io::CaseConfig& config, const RunOptions& options,
                             MeshedCase meshed);

}  // namespace softflow::simulation
