// timeseries.csv, the run's own per-step report file, declared once as its columns
// (io::ReportTable); the modules declare theirs (simulation/modules/).
#pragma once

#include <string>
#include <vector>

#include "softflow/io/report_table.hpp"
#include "softflow/simulation/drop_simulation.hpp"

namespace softflow::simulation {

/// Column formats shared by every report file: counts, and state (enough
/// digits to compare runs).
inline constexpr io::ColumnFormat kIntegerColumn = io::ColumnFormat::integer();
inline constexpr io::ColumnFormat kStateColumn = io::ColumnFormat::real(10);

/// `columns` after the two every report file starts with: step and t, from
/// the row's `report` (a StepReport).
template <class Row>
std::vector<io::Column<Row>> with_step_and_time(std::vector<io::Column<Row>> columns) {
  std::vector<io::Column<Row>> out{
      {"step", "", "step number (0: the initial state)", kIntegerColumn,
       [](const Row& r) { return r.report.step; }},
      {"t", "time", "time at the end of the step", kStateColumn,
       [](const Row& r) { return r.report.time; }}};
  for (auto& c : columns) out.push_back(std::move(c));
  return out;
}

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
