// Parameter sweeps: a case file in which parameters are lists, expanded into one case per
// combination.
#pragma once

#include <string>
#include <vector>

#include "softflow/io/case_config.hpp"

namespace softflow::io {

/// One parameter a sweep varies.
struct SweepParameter {
  std::string path;                 ///< as in messages: "objects[1].capillary_number", "time.step"
  std::string name;                 ///< in directory names and table columns: "capillary_number",
                                    ///< "objects2.capillary_number"
  std::vector<std::string> labels;  ///< each value as written in directory names ("0.05")
  std::vector<double> numbers;      ///< each value as a number (NaN if it is not one)
};

/// One combination: its label (the subdirectory name), the case file text,
/// and the validated case.
struct SweepCase {
  std::string label;        ///< e.g. "capillary_number_0.05__viscosity_ratio_1.4"
  std::vector<int> choice;  ///< index into each parameter's values
  std::string toml_text;    ///< the case file of this combination
  CaseConfig config;
};

struct Sweep {
  std::string name;       ///< the sweep's [case] name
  std::string directory;  ///< the sweep's [output] directory; case k runs in directory/label_k
  std::vector<SweepParameter> parameters;
  std::vector<SweepCase> cases;  ///< every combination, the first parameter varying slowest
};

/// A key whose value is a list where the schema wants a single value: a
/// number, string or boolean given as [a, b, ...], or a vector (centre,
/// semi_axes, rotation_deg) given as a list of vectors. Any key of any
/// table may be varied so, [[objects]] keys per object. Empty when the case
/// file is an ordinary one. Throws InputError on TOML syntax errors.
std::vector<SweepParameter> sweep_parameters(const std::string& toml_text,
                                             const std::string& source_name);

/// Every combination of the listed values as its own case: [case] name
/// becomes "<name>_<label>" and [output] directory "<directory>/<label>".
/// Each case is validated in full; a problem is reported once, naming the
/// combination. Throws InputError (also for an empty list).
Sweep expand_sweep(const std::string& toml_text, const std::string& source_name);

}  // namespace softflow::io
