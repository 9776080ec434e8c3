// The remesh triggers of [remesh] (simulation/remesh_triggers,
// geometry/object_gaps; issue 31): the least-resolved narrow gap of a mesh,
// squeezed when an object is carried towards a wall and restored by a
// remesh; each trigger's reason; a remesh that leaves its condition standing
// waits for a further 5 % drop; the time of the last remesh survives a
// checkpoint; the keys' refusals.
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/geometry/object_gaps.hpp"
#include "softflow/geometry/remesh.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/physics/ale/mesh_motion.hpp"
#include "softflow/simulation/remesh_triggers.hpp"
#include "softflow/simulation/run_ledger.hpp"
#include "softflow/simulation/run_support.hpp"
#include "support/input_errors.hpp"

namespace softflow {
namespace {

// A sphere 0.3 R below the upper wall (narrower than two interface elements:
// the mesher refines the gap to gap_elements = 2 across).
const std::string kNearWall =
    "[cell]\nlength = 6.0\nheight = 3.0\nwidth = 6.0\n[mesh]\nequator_nodes = 12\n"
    "far_size = 2.0\n[[objects]]\ncentre = [0.0, 0.2, 0.0]\nviscosity_ratio = 1.0\n"
    "capillary_number = 0.2\n";

std::string error_of(const std::string& text) { return test_support::case_error_of(text); }

TEST(ObjectGaps, ASqueezedWallGapHasFewerElementsAndARemeshRestoresThem) {
  const io::CaseConfig config = io::parse_case(kNearWall, "c.toml");
  mesh::Mesh m = simulation::build_mesh(config).mesh;
  // (The lower wall's gap, 0.7 R, is refined too; 0.5 measures the upper only.)
  const auto before = geometry::least_resolved_gap(m, 0.5);
  ASSERT_TRUE(before.has_value());
  EXPECT_EQ(before->object, 1);
  EXPECT_EQ(before->other, 0);
  EXPECT_EQ(before->resolution.side, 1);
  // The interface node nearest the wall lies on the sphere: the gap is 0.3
  // up to the sag of the node ring near the pole.
  EXPECT_GE(before->resolution.gap, 0.3 - 1e-12);
  EXPECT_LT(before->resolution.gap, 0.3 + 0.05);
  EXPECT_GT(before->resolution.elements_across(), 1.5);
  // Carried 0.12 towards the wall, the gap's elements are squeezed, not added.
  physics::carry_objects(m, Eigen::Vector3d(0.0, 0.12, 0.0));
  const auto squeezed = geometry::least_resolved_gap(m, 0.5);
  ASSERT_TRUE(squeezed.has_value());
  EXPECT_NEAR(squeezed->resolution.gap, before->resolution.gap - 0.12, 1e-9);
  EXPECT_LT(squeezed->resolution.elements_across(), 0.75 * before->resolution.elements_across());
  // A remesh of the moved domain resolves the new gap again.
  const auto remeshed = geometry::remesh(config.shear_cell_spec(), m);
  const auto restored = geometry::least_resolved_gap(remeshed.mesh, 0.5);
  ASSERT_TRUE(restored.has_value());
  EXPECT_NEAR(restored->resolution.gap, squeezed->resolution.gap, 1e-12);  // interface kept
  // (Measured: 2.26 across the 0.3 gap as meshed, 1.53 carried, 1.94 remeshed;
  // the mesher aims at mesh.gap_elements = 2.)
  EXPECT_GT(restored->resolution.elements_across(), 1.2 * squeezed->resolution.elements_across());
  EXPECT_GT(restored->resolution.elements_across(), 0.9 * config.sizing.elements_across_gaps());
  std::printf("elements across the wall gap: %.2f (gap %.3f), carried %.2f (gap %.3f), remeshed %.2f\n",
              before->resolution.elements_across(), before->resolution.gap,
              squeezed->resolution.elements_across(), squeezed->resolution.gap,
              restored->resolution.elements_across());
  // Gaps wider than asked are not measured.
  EXPECT_FALSE(geometry::least_resolved_gap(remeshed.mesh, 0.05).has_value());
}

TEST(ObjectGaps, TheGapBetweenTwoObjectsIsFoundBetweenTheirClosestNodes) {
  const io::CaseConfig config = io::parse_case(
      "[cell]\nlength = 8.0\nheight = 6.0\nwidth = 6.0\n[mesh]\nequator_nodes = 12\n"
      "far_size = 2.0\n[[objects]]\ncentre = [-1.2, 0.0, 0.0]\n[[objects]]\n"
      "centre = [1.2, 0.0, 0.0]\n",
      "c.toml");
  const mesh::Mesh m = simulation::build_mesh(config).mesh;
  const auto gap = geometry::least_resolved_gap(m, 1.0);  // the walls are 2 away
  ASSERT_TRUE(gap.has_value());
  EXPECT_EQ(gap->object, 1);
  EXPECT_EQ(gap->other, 2);
  EXPECT_GE(gap->resolution.gap, 0.4 - 1e-12);
  EXPECT_LT(gap->resolution.gap, 0.4 + 0.1);
  EXPECT_GT(gap->resolution.tets_crossed, 0);
}

TEST(RemeshTriggers, EachTriggerSaysWhyAndOnlyWhenItsConditionHolds) {
  const io::CaseConfig config = io::parse_case(
      kNearWall + "[remesh]\nquality = 0.2\ninterval = 2.0\ngap_elements = 1.0\n", "c.toml");
  simulation::RemeshTriggers triggers(config);
  simulation::MeshCondition fine{.time = 1.0, .quality = 0.3, .gap_elements = 2.0, .gap_description = ""};
  EXPECT_EQ(triggers.due(fine, 0.0), "");
  auto poor = fine;
  poor.quality = 0.15;
  EXPECT_NE(triggers.due(poor, 0.0).find("remesh.quality"), std::string::npos);
  auto squeezed = fine;
  squeezed.gap_elements = 0.8;
  squeezed.gap_description = "object 1 to the upper wall";
  EXPECT_NE(triggers.due(squeezed, 0.0).find("object 1 to the upper wall crossed by 0.80 elements"),
            std::string::npos);
  auto later = fine;
  later.time = 2.5;
  EXPECT_NE(triggers.due(later, 0.0).find("remesh.interval"), std::string::npos);
  EXPECT_EQ(triggers.due(later, 1.0), "");  // 1.5 since the last remesh
  // The remesher's best mesh is still below the quality: not again before a 5 % drop.
  triggers.remeshed({.time = 1.0, .quality = 0.18, .gap_elements = 2.0, .gap_description = ""});
  poor.quality = 0.175;
  EXPECT_EQ(triggers.due(poor, 1.0), "");
  poor.quality = 0.17;
  EXPECT_NE(triggers.due(poor, 1.0), "");
  // A failed remesh: both wait.
  triggers.failed(squeezed);
  EXPECT_EQ(triggers.due(squeezed, 1.0), "");
  squeezed.gap_elements = 0.7;
  EXPECT_NE(triggers.due(squeezed, 1.0), "");
  // A gap wider than the mesher refines is not measured: +infinity elements.
  const auto far = triggers.measure(simulation::build_mesh(io::parse_case(
                                        "[[objects]]\n[mesh]\nequator_nodes = 12\n", "c.toml"))
                                        .mesh,
                                    0.0, 0.3);
  EXPECT_TRUE(std::isinf(far.gap_elements));
}

TEST(RemeshTriggers, TheLastRemeshTimeIsSavedWithTheCheckpoint) {
  const io::CaseConfig config =
      io::parse_case(kNearWall + "[remesh]\ninterval = 2.0\n", "c.toml");
  simulation::RunLedger ledger;
  ledger.last_remesh_time = 3.25;
  const auto back = simulation::ledger_from_json(simulation::to_json(ledger).dump(), config);
  EXPECT_EQ(back.last_remesh_time, 3.25);
}

TEST(RemeshTriggers, KeysAreCheckedAndPrinted) {
  const std::string e = error_of(kNearWall + "[remesh]\ngap_elements = 2.0\n");
  EXPECT_NE(e.find("remesh.gap_elements"), std::string::npos) << e;
  EXPECT_NE(e.find("mesh.gap_elements = 2"), std::string::npos) << e;
  EXPECT_EQ(error_of(kNearWall + "[remesh]\ngap_elements = 1.5\n"), "");
  std::string three = kNearWall;
  three.replace(three.find("far_size"), 0, "gap_elements = 3\n");
  EXPECT_EQ(error_of(three + "[remesh]\ngap_elements = 2.0\n"), "");
  EXPECT_NE(error_of(kNearWall + "[remesh]\ninterval = -1.0\n").find("remesh.interval"),
            std::string::npos);
  // A case with only a schedule prints its [remesh] table (and reads back the same).
  const auto c = io::parse_case(kNearWall + "[remesh]\ninterval = 2.0\n", "c.toml");
  const std::string toml = io::to_toml(c);
  EXPECT_NE(toml.find("interval = 2.0"), std::string::npos) << toml;
  EXPECT_EQ(io::to_toml(io::parse_case(toml, "c.toml")), toml);
}

}  // namespace
}  // namespace softflow
