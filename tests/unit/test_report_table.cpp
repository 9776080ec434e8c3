// Report files declared once (io::ReportTable, simulation/report_tables): header,
// rows and documentation from one list of columns.
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "softflow/io/report_table.hpp"
#include "softflow/simulation/report_tables.hpp"

namespace softflow {
namespace {

struct Sample {
  int id;
  double x;
};

io::ReportTable<Sample> sample_table() {
  return {"sample.csv", "sample", "For the test.",
          {{"id", "", "the id", io::ColumnFormat::integer(), [](const Sample& s) { return s.id; }},
           {"x", "m", "a length", io::ColumnFormat::real(4), [](const Sample& s) { return s.x; }},
           {"x2", "m^2", "its square", io::ColumnFormat::real(10),
            [](const Sample& s) { return s.x * s.x; }}}};
}

TEST(ReportTable, HeaderRowsAndDocumentationFollowTheColumns) {
  const auto table = sample_table();
  EXPECT_EQ(table.header(), "id,x,x2\n");
  EXPECT_EQ(table.row({7, 1.0 / 3.0}), "7,0.3333,0.1111111111\n");
  EXPECT_EQ(table.row({-2, std::numeric_limits<double>::quiet_NaN()}), "-2,nan,nan\n");
  const std::string doc = table.markdown();
  EXPECT_NE(doc.find("## sample.csv"), std::string::npos) << doc;
  EXPECT_NE(doc.find("| `x` | m | a length |"), std::string::npos) << doc;
  EXPECT_NE(doc.find("| `id` | - | the id |"), std::string::npos) << doc;
}

TEST(ReportTables, TheTimeSeriesKeepsItsColumnsAndFormat) {
  // The columns and digits timeseries.csv had before it was declared (the
  // regression references and every plotting script read them by name).
  EXPECT_EQ(simulation::timeseries_header(),
            "step,t,object,D,theta_deg,L,B,W,xc,yc,zc,uc,vc,wc,volume,area,ellipsoid_dev,"
            "min_quality,stokes_iterations,step_seconds,dt,interface_change\n");
  simulation::StepReport r;
  r.step = 3;
  r.time = 0.15;
  r.min_quality = 0.123456789;
  r.stokes_iterations = 12;
  r.step_seconds = 1.23456;
  r.dt = 0.05;
  simulation::ObjectState o;
  o.object = 1;
  o.deformation = 0.0123456789012;
  r.objects.push_back(o);
  const std::string row = simulation::timeseries_rows(r);
  EXPECT_EQ(row.substr(0, row.find(",0,0,0,")), "3,0.15,1,0.0123456789");
  EXPECT_NE(row.find(",0.123457,12,1.235,0.05,nan\n"), std::string::npos) << row;
}

TEST(ReportTables, DocsOutputColumnsIsUpToDate) {
  const std::string path = std::string(SOFTFLOW_SOURCE_DIR) + "/docs/output_columns.md";
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), simulation::output_columns_markdown())
      << "docs/output_columns.md is out of date: run `build/softflow columns > "
         "docs/output_columns.md`";
}

}  // namespace
}  // namespace softflow
