// solver.type = "auto": direct up to simulation::kDirectSolverLimit unknowns, iterative above.
#include <gtest/gtest.h>

#include "softflow/geometry/shear_cell.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/simulation/run_support.hpp"

using namespace softflow;

TEST(SolverChoice, AutoIsDirectBelowTheLimitAndExplicitChoicesAreKept) {
  io::CaseConfig config;
  config.objects.emplace_back();
  geometry::ShearCellSpec spec;
  spec.box.length = spec.box.height = spec.box.width = 8.0;
  spec.objects.push_back(geometry::ObjectSpec{});
  spec.sizing.equator_nodes = 16;
  spec.sizing.far_size = 2.0;
  const auto mesh = geometry::build_shear_cell(spec);
  ASSERT_LT(physics::make_stokes_dof_map(mesh, false).n_dofs(), simulation::kDirectSolverLimit);

  EXPECT_EQ(config.solver, io::SolverType::automatic);  // the default
  EXPECT_EQ(simulation::solver_settings(config, mesh).method, la::SaddlePointMethod::direct);
  config.solver = io::SolverType::iterative;
  EXPECT_EQ(simulation::solver_settings(config, mesh).method, la::SaddlePointMethod::iterative);
  config.solver = io::SolverType::direct;
  EXPECT_EQ(simulation::solver_settings(config, mesh).method, la::SaddlePointMethod::direct);
}

TEST(SolverChoice, AutoSwitchesToIterativeAboveTheLimit) {
  using simulation::kDirectSolverLimit;
  using simulation::solver_method;
  EXPECT_EQ(solver_method(io::SolverType::automatic, kDirectSolverLimit), la::SaddlePointMethod::direct);
  EXPECT_EQ(solver_method(io::SolverType::automatic, kDirectSolverLimit + 1), la::SaddlePointMethod::iterative);
  EXPECT_EQ(solver_method(io::SolverType::direct, 10 * kDirectSolverLimit), la::SaddlePointMethod::direct);
  EXPECT_EQ(solver_method(io::SolverType::iterative, 100), la::SaddlePointMethod::iterative);
}
