#include "softflow/simulation/report_tables.hpp"

#include "softflow/simulation/step_module.hpp"

namespace softflow::simulation {

namespace {

using io::Column;
using io::ColumnFormat;
constexpr ColumnFormat kInteger = kIntegerColumn;
constexpr ColumnFormat kFull = kStateColumn;
constexpr ColumnFormat kShort = ColumnFormat::real(6);  // diagnostics
constexpr ColumnFormat kTiming = ColumnFormat::real(4);

}  // namespace

const io::ReportTable<ObjectRow>& timeseries_table() {
  using C = Column<ObjectRow>;
  static const io::ReportTable<ObjectRow> table(
      "timeseries.csv", "object and step",
      "Shape from the least-squares ellipsoid through the interface nodes (eq. 2.57); "
      "volume, area and centre of volume on the curved P2 surface.",
      with_step_and_time<ObjectRow>(
           std::vector<C>{
               {"object", "", "object number (1-based, as [[objects]])", kInteger,
                [](const ObjectRow& r) { return r.object.object; }},
               {"D", "", "deformation parameter (L - B) / (L + B)", kFull,
                [](const ObjectRow& r) { return r.object.deformation; }},
               {"theta_deg", "deg", "angle of the major axis to the flow direction (nan below D = "
                "1e-4, where it is undefined)", kFull,
                [](const ObjectRow& r) { return r.object.theta_deg; }},
               {"L", "length", "longest semi-axis in the shear plane", kFull,
                [](const ObjectRow& r) { return r.object.L; }},
               {"B", "length", "shortest semi-axis in the shear plane", kFull,
                [](const ObjectRow& r) { return r.object.B; }},
               {"W", "length", "semi-axis along the vorticity", kFull,
                [](const ObjectRow& r) { return r.object.W; }},
               {"xc", "length", "centre of volume, x (flow)", kFull,
                [](const ObjectRow& r) { return r.object.centre.x(); }},
               {"yc", "length", "centre of volume, y (gradient)", kFull,
                [](const ObjectRow& r) { return r.object.centre.y(); }},
               {"zc", "length", "centre of volume, z (vorticity)", kFull,
                [](const ObjectRow& r) { return r.object.centre.z(); }},
               {"uc", "length/time", "velocity of the centre of volume, x (eqs. 2.51-2.54)", kFull,
                [](const ObjectRow& r) { return r.object.centre_velocity.x(); }},
               {"vc", "length/time", "velocity of the centre of volume, y: the migration velocity",
                kFull, [](const ObjectRow& r) { return r.object.centre_velocity.y(); }},
               {"wc", "length/time", "velocity of the centre of volume, z", kFull,
                [](const ObjectRow& r) { return r.object.centre_velocity.z(); }},
               {"volume", "length^3", "enclosed volume", kFull,
                [](const ObjectRow& r) { return r.object.volume; }},
               {"area", "length^2", "interface area", kFull,
                [](const ObjectRow& r) { return r.object.area; }},
               {"ellipsoid_dev", "", "largest node distance from the fitted ellipsoid, relative to "
                "its size (the thesis accepts 2-3 %)", kShort,
                [](const ObjectRow& r) { return r.object.ellipsoid_deviation; }},
               {"min_quality", "", "smallest element quality (scaled Jacobian) of the whole mesh",
                kShort, [](const ObjectRow& r) { return r.report.min_quality; }},
               {"stokes_iterations", "", "Krylov iterations of the step's Stokes solve", kInteger,
                [](const ObjectRow& r) { return r.report.stokes_iterations; }},
               {"step_seconds", "s", "wall time of the step", kTiming,
                [](const ObjectRow& r) { return r.report.step_seconds; }},
               {"dt", "time", "size of the step", kFull,
                [](const ObjectRow& r) { return r.report.dt; }},
               {"interface_change", "", "largest predicted-to-corrected interface node move over "
                "the object radius: the step's error estimate (nan at a BDF1 step)", kShort,
                [](const ObjectRow& r) { return r.report.interface_change; }}}));
  return table;
}

std::string timeseries_header() { return timeseries_table().header(); }

std::string timeseries_rows(const StepReport& r) {
  std::string out;
  for (const auto& o : r.objects) out += timeseries_table().row({r, o});
  return out;
}

std::string output_columns_markdown() {
  auto modules_markdown = [] {
    std::string out;
    for (const auto& type : module_types()) out += type.columns_markdown();
    return out;
  };
  return "# The columns of a run's report files\n\n"
         "Generated from their declarations (`src/softflow/simulation/report_tables.cpp`, and each "
         "module's in `src/softflow/simulation/modules/`) by "
         "`softflow columns`; lengths, times and stresses are in the case file's own units.\n\n" +
         timeseries_table().markdown() + modules_markdown();
}

}  // namespace softflow::simulation
