// softflow converge's levels: every element size shrinks by one ratio,
// the objects' interior included.
#include <cmath>

#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/simulation/convergence.hpp"

using namespace softflow;

namespace {

constexpr const char* kCase = R"([[objects]]
[mesh]
equator_nodes = 20
far_size = 4.0
growth = 0.5
{}
[time]
step = 0.05
end = 1.0
)";

std::string case_with(const std::string& interior) {
  std::string text = kCase;
  text.replace(text.find("{}"), 2, interior);
  return text;
}

}  // namespace

TEST(MeshLevels, FarSizeGrowthAndInteriorGrowthShrinkWithTheInterfaceSize) {
  simulation::ConvergeOptions options;
  options.levels = 3;
  options.factor = 1.5;
  const auto sweep = simulation::mesh_levels(case_with("interior_growth = 0.2"), "case.toml", options);
  ASSERT_EQ(sweep.cases.size(), 3u);
  for (const auto& c : sweep.cases) {
    const double scale = 20.0 / c.config.sizing.equator_nodes;
    EXPECT_DOUBLE_EQ(c.config.sizing.far_size, 4.0 * scale);
    EXPECT_DOUBLE_EQ(c.config.sizing.growth, 0.5 * scale);
    ASSERT_TRUE(c.config.sizing.interior_growth.has_value());
    EXPECT_DOUBLE_EQ(*c.config.sizing.interior_growth, 0.2 * scale);
  }
  EXPECT_EQ(sweep.cases[2].config.sizing.equator_nodes, 45);  // round(20 x 1.5^2)
}

TEST(MeshLevels, AnUnsetInteriorGrowthStaysTheGrowthAndZeroStaysZero) {
  simulation::ConvergeOptions options;
  options.levels = 3;
  for (const auto& c : simulation::mesh_levels(case_with(""), "case.toml", options).cases)
    EXPECT_FALSE(c.config.sizing.interior_growth.has_value());
  for (const auto& c : simulation::mesh_levels(case_with("interior_growth = 0"), "case.toml", options).cases)
    EXPECT_EQ(c.config.sizing.interior_growth, 0.0);
}

TEST(MeshLevels, ExplicitEquatorNodesAreTheLevelsWithEverySizeScaled) {
  simulation::ConvergeOptions options;
  options.equator_nodes = {20, 25, 31, 39, 49, 61, 78};  // 76 (factor 1.25) fails in gmsh
  const auto sweep = simulation::mesh_levels(case_with(""), "case.toml", options);
  ASSERT_EQ(sweep.cases.size(), 7u);
  for (std::size_t k = 0; k < sweep.cases.size(); ++k) {
    const auto& c = sweep.cases[k];
    EXPECT_EQ(c.config.sizing.equator_nodes, options.equator_nodes[k]);
    EXPECT_EQ(c.label, "N" + std::to_string(options.equator_nodes[k]));
    EXPECT_DOUBLE_EQ(c.config.sizing.far_size, 4.0 * 20.0 / options.equator_nodes[k]);
    EXPECT_DOUBLE_EQ(c.config.sizing.growth, 0.5 * 20.0 / options.equator_nodes[k]);
  }
}

TEST(MeshLevels, ExplicitEquatorNodesMustBeThreeToEightAscendingCounts) {
  for (const std::vector<int>& bad : {std::vector<int>{20, 25}, {20, 25, 25}, {30, 25, 40}, {6, 20, 25},
                                     {10, 11, 12, 13, 14, 15, 16, 17, 18}}) {
    simulation::ConvergeOptions options;
    options.equator_nodes = bad;
    try {
      (void)simulation::mesh_levels(case_with(""), "case.toml", options);
      ADD_FAILURE() << "accepted " << ::testing::PrintToString(bad);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--equator-nodes"), std::string::npos) << e.what();
    }
  }
}

TEST(MeshLevels, TwoLevelsNeedAKnownOrderWithinItsRange) {
  simulation::ConvergeOptions options;
  options.levels = 2;
  const auto message = [&] {
    try {
      (void)simulation::mesh_levels(case_with(""), "case.toml", options);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message().find("--levels 2: between 3 and 8"), std::string::npos) << message();
  options.order = 3.0;
  EXPECT_EQ(simulation::mesh_levels(case_with(""), "case.toml", options).cases.size(), 2u);
  options.equator_nodes = {20, 25};
  EXPECT_EQ(simulation::mesh_levels(case_with(""), "case.toml", options).cases.size(), 2u);
  options.equator_nodes = {20};
  EXPECT_NE(message().find("--equator-nodes 20: 2 to 8 levels"), std::string::npos) << message();
  options.equator_nodes.clear();
  options.order = 15.0;
  EXPECT_NE(message().find("--order 15"), std::string::npos) << message();
}
