// solver.type = "auto": direct up to la::kDirectSolverLimit unknowns,
// iterative above, decided by the Stokes system from its own dof count.
#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/la/saddle_point_solver.hpp"
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
  auto method_of = [&](const io::CaseConfig& c) {
    return physics::StokesSystem(mesh, simulation::solver_settings(c), false).settings().method;
  };

  EXPECT_EQ(config.solver, io::SolverType::automatic);  // the default
  EXPECT_EQ(simulation::solver_settings(config).method, la::SaddlePointMethod::automatic);
  physics::StokesSystem stokes(mesh, simulation::solver_settings(config), false);
  ASSERT_LT(stokes.dofs().n_dofs(), la::kDirectSolverLimit);
  EXPECT_EQ(stokes.settings().method, la::SaddlePointMethod::direct);  // resolved by its size
  config.solver = io::SolverType::iterative;
  EXPECT_EQ(method_of(config), la::SaddlePointMethod::iterative);
  config.solver = io::SolverType::direct;
  EXPECT_EQ(method_of(config), la::SaddlePointMethod::direct);
}

TEST(SolverChoice, AutoSwitchesToIterativeAboveTheLimit) {
  using la::kDirectSolverLimit;
  using la::resolve_method;
  using la::SaddlePointMethod;
  EXPECT_EQ(resolve_method(SaddlePointMethod::automatic, kDirectSolverLimit), SaddlePointMethod::direct);
  EXPECT_EQ(resolve_method(SaddlePointMethod::automatic, kDirectSolverLimit + 1), SaddlePointMethod::iterative);
  EXPECT_EQ(resolve_method(SaddlePointMethod::direct, 10 * kDirectSolverLimit), SaddlePointMethod::direct);
  EXPECT_EQ(resolve_method(SaddlePointMethod::iterative, 100), SaddlePointMethod::iterative);
}

TEST(SolverChoice, AnUnresolvedMethodIsRefusedBySolverItself) {
  la::SaddlePointSettings settings;
  settings.method = la::SaddlePointMethod::automatic;
  EXPECT_THROW(la::SaddlePointSolver(settings, {}, nullptr), SolverError);
}
