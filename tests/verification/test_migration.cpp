// Cross-stream migration (thesis chapter 3) through the migration module and
// `softflow migration`'s assembly: a drop above the centre plane of a confined
// cell (beta = 0.4) and its mirror image below it. The rotation by 180 deg about
// the vorticity axis maps simple shear onto itself and one case onto the other,
// so v_p must be equal and opposite (the two meshes are not mirror images: this
// measures the discretisation's asymmetry too), pointing to the centre plane
// (wall-induced migration of a deformable drop in Stokes flow), and the master
// curve assembled from the two runs must change sign between them: a stable
// neutral height at the centre.
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <mpi.h>

#include "softflow/common/error.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/simulation/drop_run.hpp"
#include "softflow/simulation/migration_curves.hpp"
#include "softflow/simulation/run_support.hpp"

using namespace softflow;
namespace fs = std::filesystem;

namespace {

io::CaseConfig confined_drop(double y0, const fs::path& directory) {
  return io::parse_case(
      "[cell]\nlength = 8.0\nheight = 5.0\nwidth = 8.0\n"
      "[[objects]]\ncentre = [0.0, " + std::to_string(y0) + ", 0.0]\ncapillary_number = 0.2\n"
      "[mesh]\nequator_nodes = 16\nfar_size = 1.5\n"
      "[time]\nstep = 0.05\nend = 0.6\n"
      "[output]\nfields = false\ndirectory = \"" + directory.string() + "\"\n",
      y0 > 0 ? "above" : "below");
}

nlohmann::json run(const io::CaseConfig& config) {
  simulation::RunOptions options;
  options.quiet = true;
  options.overwrite = true;
  return simulation::run_drop_case(config, options, simulation::build_mesh(config));
}

}  // namespace

TEST(Migration, MirrorImagesMigrateEquallyTowardsTheCentre) {
  const fs::path above = fs::temp_directory_path() / "softflow_migration_above";
  const fs::path below = fs::temp_directory_path() / "softflow_migration_below";
  const auto up = run(confined_drop(0.5, above))["final_migration"].at(0);
  const auto down = run(confined_drop(-0.5, below))["final_migration"].at(0);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) return;

  const double v_up = up["v_p"], v_down = down["v_p"];
  EXPECT_LT(v_up, 0.0);  // down, to the centre plane
  EXPECT_GT(v_down, 0.0);
  EXPECT_LT(std::abs(v_up + v_down), 0.1 * std::abs(v_up)) << v_up << " " << v_down;
  // y_p,max = H/2 - R = 1.5; the gap to the nearer wall ~ H/2 - y_p - 0.99: the
  // drop at D ~ 0.18, tilted ~38 deg, reaches 0.99 R above its centre.
  EXPECT_NEAR(up["y_p_rel"].get<double>(), up["y_p"].get<double>() / 1.5, 1e-6);
  EXPECT_EQ(up["nearest_wall"], 1);
  EXPECT_EQ(down["nearest_wall"], -1);
  EXPECT_GT(up["wall_gap"].get<double>(), 0.95);
  EXPECT_LT(up["wall_gap"].get<double>(), 1.05);

  // The two runs' rows after the first 0.2 time units, as a master curve.
  const auto curves = simulation::assemble_migration({above, below}, 0.21, 0.1);
  EXPECT_NEAR(curves.blockage_ratio, 0.4, 1e-12);
  EXPECT_EQ(curves.points.size(), 16u);  // 8 rows each, t = 0.25 ... 0.6
  // Stretches of 0.1 from t = 0.25: 0.25-0.35, 0.35-0.45, 0.45-0.6 (the 0.05
  // left joins the last), three per run, each the slope of y_p over it.
  ASSERT_EQ(curves.segments.size(), 6u);
  for (const auto& s : curves.segments) EXPECT_EQ(s.v_p > 0.0, s.y_rel < 0.0);
  ASSERT_EQ(curves.neutral.size(), 1u);
  EXPECT_TRUE(curves.neutral[0].stable());
  EXPECT_LT(std::abs(curves.neutral[0].y_rel), curves.neutral[0].error);
  EXPECT_FALSE(curves.slope.has_value());  // no point within |y_p / y_p,max| <= 0.1

  // Runs of another particle do not make one curve.
  const fs::path other = fs::temp_directory_path() / "softflow_migration_other";
  auto config = confined_drop(0.5, other);
  config.box.height = 6.0;
  config.time.end = 0.1;
  run(config);
  EXPECT_THROW(simulation::assemble_migration({above, other}, 0.0), InputError);
  for (const auto& d : {above, below, other}) fs::remove_all(d);
}
