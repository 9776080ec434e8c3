// timeseries.csv, the run's own per-step report file, declared once as its columns
// (io::ReportTable); the modules declare theirs (simulation/modules/).
#pragma once

#include <string>

#include "softflow/io/report_table.hpp"
#include "softflow/simulation/drop_simulation.hpp"

namespace softflow::simulation {

/// What one row is made from.
struct ObjectRow {
  const StepReport& report;
  const ObjectState& object;
};

/// timeseries.csv: one row per object and step.
const io::ReportTable<ObjectRow>& timeseries_table();

/// The header and the rows of `report`.
std::string timeseries_header();
std::string timeseries_rows(const StepReport& report);

/// docs/output_columns.md: the columns of timeseries.csv and of every built-in
/// module's files (`softflow columns`).
std::string output_columns_markdown();

}  // namespace softflow::simulation
