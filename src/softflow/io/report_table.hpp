// A CSV report declared once: each column's name, unit, meaning, print format and value,
// from which the header, the rows and the documentation's column reference all follow.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace softflow::io {

/// A cell of a summary table (sweep, converge, moduli, response): x to
/// `digits` significant digits, empty where it is not finite (nothing
/// measured there).
inline std::string table_number(double x, int digits) {
  return std::isfinite(x) ? fmt::format("{:.{}g}", x, digits) : std::string();
}

/// How a column prints: an integer, or a real to `digits` significant digits.
struct ColumnFormat {
  int digits = 10;  ///< 0: an integer
  static constexpr ColumnFormat integer() { return {0}; }
  static constexpr ColumnFormat real(int digits) { return {digits}; }
};

/// One column of a report whose rows are made from a `Row` (e.g. a step's
/// report and one object of it).
template <class Row>
struct Column {
  std::string name;
  std::string unit;     ///< "" for a pure number or a count
  std::string meaning;  ///< one line for the documentation
  ColumnFormat format;
  std::function<double(const Row&)> value;
};

/// A report file (e.g. timeseries.csv) as its columns. Adding a quantity is
/// adding one Column: the header, every row and the documentation follow.
template <class Row>
class ReportTable {
 public:
  ReportTable(std::string file, std::string one_row_per, std::string about,
              std::vector<Column<Row>> columns)
      : file_(std::move(file)),
        one_row_per_(std::move(one_row_per)),
        about_(std::move(about)),
        columns_(std::move(columns)) {}

  [[nodiscard]] const std::string& file() const { return file_; }
  [[nodiscard]] const std::vector<Column<Row>>& columns() const { return columns_; }

  /// The CSV header line, with its newline.
  [[nodiscard]] std::string header() const {
    std::string out;
    for (std::size_t c = 0; c < columns_.size(); ++c) out += (c ? "," : "") + columns_[c].name;
    return out + "\n";
  }

  /// One CSV line, with its newline. NaN prints as "nan".
  [[nodiscard]] std::string row(const Row& r) const {
    std::string out;
    for (std::size_t c = 0; c < columns_.size(); ++c) {
      if (c) out += ',';
      const double v = columns_[c].value(r);
      const int digits = columns_[c].format.digits;
      if (digits == 0)
        out += fmt::format("{}", static_cast<long long>(v));
      else
        out += fmt::format("{:.{}g}", v, digits);
    }
    return out + "\n";
  }

  /// One row as a JSON object {column name: value}, for summary.json; the
  /// columns named in `skip` (e.g. step and t, said elsewhere) left out. NaN
  /// becomes null, integer columns integers.
  [[nodiscard]] nlohmann::json json_row(const Row& r, const std::vector<std::string>& skip = {}) const {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& c : columns_) {
      if (std::find(skip.begin(), skip.end(), c.name) != skip.end()) continue;
      const double v = c.value(r);
      if (c.format.digits == 0) out[c.name] = static_cast<long long>(v);
      else out[c.name] = std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
    }
    return out;
  }

  /// The documentation's section on this file: what a row is, then a table
  /// of the columns (name, unit, meaning).
  [[nodiscard]] std::string markdown() const {
    std::string out = fmt::format("## {}\n\nOne row per {}. {}\n\n| column | unit | meaning |\n"
                                  "|---|---|---|\n",
                                  file_, one_row_per_, about_);
    for (const auto& c : columns_)
      out += fmt::format("| `{}` | {} | {} |\n", c.name, c.unit.empty() ? "-" : c.unit, c.meaning);
    return out + "\n";
  }

 private:
  std::string file_, one_row_per_, about_;
  std::vector<Column<Row>> columns_;
};

}  // namespace softflow::io
