// The per-step report files of a run in time, each declared once as its columns
// (io::ReportTable): timeseries.csv, stress.csv, slip.csv.
#pragma once

#include <string>

#include "softflow/io/report_table.hpp"
#include "softflow/simulation/drop_simulation.hpp"

namespace softflow::simulation {

/// What one row of each file is made from.
struct ObjectRow {
  const StepReport& report;
  const ObjectState& object;
};
struct StressRow {
  const StepReport& report;
  const RegionStress& stress;
};
struct SlipRow {
  const StepReport& report;
  int object;  ///< 1-based
  const physics::SlipMeasures& slip;
};

/// timeseries.csv: one row per object and step.
const io::ReportTable<ObjectRow>& timeseries_table();
/// stress.csv: one row per region with a conformation tensor and step (viscoelastic runs).
const io::ReportTable<StressRow>& stress_table();
/// slip.csv: one row per object and step (runs with interfacial slip).
const io::ReportTable<SlipRow>& slip_table();

/// The header and the rows of `report` for each file.
std::string timeseries_header();
std::string timeseries_rows(const StepReport& report);
std::string stress_header();
std::string stress_rows(const StepReport& report);
std::string slip_header();
std::string slip_rows(const StepReport& report);

/// docs/output_columns.md: every report file's columns (`softflow columns`).
std::string output_columns_markdown();

}  // namespace softflow::simulation
