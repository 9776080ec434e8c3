// The iterative Stokes solver's initial guess in a time loop ([solver]
// initial_guess): the line through the last two solutions, extrapolated a step
// on, against the last solution alone. Data affine in time make the solution
// affine in time, so the extrapolated guess is the answer up to the earlier
// solves' residuals, and the solve needs (almost) no iterations.
#include <gtest/gtest.h>

#include <optional>
#include <vector>

#include "softflow/geometry/shear_cell.hpp"
#include "softflow/la/saddle_point_solver.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"

using namespace softflow;
using Eigen::Vector3d;

namespace {

mesh::Mesh unit_drop_mesh() {
  geometry::ShearCellSpec spec;
  spec.box.length = spec.box.height = spec.box.width = 6.0;
  spec.objects.push_back(geometry::ObjectSpec{});
  spec.sizing.equator_nodes = 12;
  spec.sizing.far_size = 2.0;
  return geometry::build_shear_cell(spec);
}

/// A drop (lambda = 2, Gamma = 1) in the shear u = s (y, 0, 0) of the walls,
/// s = 1 + t: the solution is affine in t (tension's part plus s times the shear's).
physics::StokesProblem problem_at(const mesh::Mesh& mesh, double t) {
  physics::StokesProblem p;
  p.viscosity = {1.0, 2.0};
  p.interfacial_tension = {1.0};
  const double s = 1.0 + t;
  p.boundary_velocity = [s](const Vector3d& x) { return Vector3d(s * x.y(), 0.0, 0.0); };
  p.pressure_gauge_node = physics::default_pressure_gauge_node(mesh);
  return p;
}

struct Solve {
  int iterations = 0;
  std::vector<double> solution;
};

/// Solves at each time of `times`; the steps between them are passed to solve()
/// unless `steps` is false (solves outside a time loop).
std::vector<Solve> solve_sequence(const mesh::Mesh& mesh, bool extrapolated, const std::vector<double>& times,
                                  bool steps = true, int restart_before = -1) {
  la::SaddlePointSettings settings;
  settings.method = la::SaddlePointMethod::iterative;
  settings.extrapolated_guess = extrapolated;
  physics::StokesSystem system(mesh, settings);
  std::vector<Solve> out;
  double last = 0.0;
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (static_cast<int>(i) == restart_before) system.restart_guess_history();
    const std::optional<double> step = steps ? std::optional<double>(times[i] - last) : std::nullopt;
    const auto r = system.solve(problem_at(mesh, times[i]), physics::SolutionLayout::gathered, step);
    out.push_back({r.solve.iterations, r.solution});
    last = times[i];
  }
  return out;
}

double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0.0, size = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d = std::max(d, std::abs(a[i] - b[i]));
    size = std::max(size, std::abs(a[i]));
  }
  return d / size;
}

// Steps 0.1, 0.1, 0.15, 0.1: the line's ratio dt_n / dt_{n-1} is 1.5 at the
// third solve and 2/3 at the fourth (a step kept one solve late fails it).
const std::vector<double> kTimes{0.1, 0.2, 0.35, 0.45};
// The extrapolated guess's residual is (1 + w) r_n - w r_{n-1}, the earlier
// solves' residuals r (<= rtol |b| each) with w <= 1.5: at most 4 rtol |b|,
// which GMRES (about a factor 2 an iteration here) removes in 2-3.
constexpr int kAlongTheLine = 3;
// From the last solution the residual is the data's change over a step (the
// shear grows by 6-10 % a step here): at rtol 1e-8 many iterations.
constexpr int kFromTheLast = 10;

}  // namespace

TEST(StokesInitialGuess, ExtrapolationMakesAffineInTimeDataNearlyFree) {
  const auto mesh = unit_drop_mesh();
  const auto previous = solve_sequence(mesh, false, kTimes);
  const auto extrapolated = solve_sequence(mesh, true, kTimes);
  // The first two solves have no line to extrapolate along: the same iterations.
  for (int i = 0; i < 2; ++i) EXPECT_EQ(extrapolated[i].iterations, previous[i].iterations) << "solve " << i;
  for (std::size_t i = 2; i < kTimes.size(); ++i) {
    EXPECT_GE(previous[i].iterations, kFromTheLast) << "solve " << i;
    EXPECT_LE(extrapolated[i].iterations, kAlongTheLine) << "solve " << i;
    EXPECT_LT(largest_difference(previous[i].solution, extrapolated[i].solution), 1e-5) << "solve " << i;
  }
}

TEST(StokesInitialGuess, OnlyStepsAfterStepsAreExtrapolated) {
  const auto mesh = unit_drop_mesh();
  const auto previous = solve_sequence(mesh, false, kTimes);
  // Solves outside a time loop (no step given): always the last solution.
  const auto untimed = solve_sequence(mesh, true, kTimes, false);
  for (std::size_t i = 0; i < kTimes.size(); ++i) EXPECT_EQ(untimed[i].iterations, previous[i].iterations);
  // A restarted history (a jump of the walls before solve 2): solves 2 and 3
  // from the last solution (a line through 1 and 2 would cross the jump),
  // solve 4 along the line through 2 and 3.
  std::vector<double> times = kTimes;
  times.push_back(0.6);
  const auto longer = solve_sequence(mesh, false, times);
  const auto restarted = solve_sequence(mesh, true, times, true, 2);
  EXPECT_EQ(restarted[2].iterations, longer[2].iterations);
  EXPECT_EQ(restarted[3].iterations, longer[3].iterations);
  EXPECT_GE(longer[4].iterations, kFromTheLast);
  EXPECT_LE(restarted[4].iterations, kAlongTheLine);
}

TEST(StokesInitialGuess, ARejectedStepLeavesTheLine) {
  // An adaptive run: steps to 0.1, 0.2, 0.3; a step to 0.5 rejected; retried
  // to 0.4. Rewound, the retry extrapolates along 0.2, 0.3 (exact here);
  // kept, the rejected solve would put the line's end at 0.6.
  const auto mesh = unit_drop_mesh();
  la::SaddlePointSettings settings;
  settings.method = la::SaddlePointMethod::iterative;
  physics::StokesSystem system(mesh, settings);
  auto solve = [&](double t, double step) {
    return system.solve(problem_at(mesh, t), physics::SolutionLayout::distributed, step)
        .solve.iterations;
  };
  solve(0.1, 0.1);
  solve(0.2, 0.1);
  solve(0.3, 0.1);
  const long before = system.guess_history_mark();
  solve(0.5, 0.2);  // rejected
  system.rewind_guess_history(before);
  EXPECT_EQ(system.guess_history_mark(), before);
  EXPECT_LE(solve(0.4, 0.1), kAlongTheLine);
  EXPECT_LE(solve(0.5, 0.1), kAlongTheLine);  // and the line goes on from the retried step
  // Rewinding to where it stands changes nothing; past more than one solve
  // (not one step) restarts the line: the next solve from the last solution.
  const long now = system.guess_history_mark();
  system.rewind_guess_history(now);
  EXPECT_LE(solve(0.6, 0.1), kAlongTheLine);
  solve(0.7, 0.1);
  system.rewind_guess_history(now);
  EXPECT_GE(solve(0.8, 0.1), kFromTheLast);
}
