// Test support: solve a Stokes problem whose exact solution is known and measure the error.
#pragma once

#include <functional>
#include <random>

#include "softflow/fem/norms.hpp"
#include "support/verification/structured_box.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"

namespace softflow::test_support {

/// An exact Stokes solution: velocity, pressure and the body force they need.
struct ExactStokes {
  fem::VectorField velocity;
  fem::ScalarField pressure;
  std::function<Eigen::Vector3d(const Eigen::Vector3d&, int)> body_force;
};

struct ExactRun {
  fem::StokesErrors errors;
  int n_dofs = 0;
  double h = 0.0;
};

/// Solves with the exact velocity on every boundary face, the pressure
/// gauge at the default node set to the exact value, and returns the errors.
inline ExactRun solve_against_exact(const mesh::Mesh& mesh, const ExactStokes& exact,
                                    std::vector<double> viscosity,
                                    std::vector<double> tension = {},
                                    la::SaddlePointMethod method = la::SaddlePointMethod::direct) {
  la::SaddlePointSettings settings;
  settings.method = method;
  settings.rtol = 1e-12;
  physics::StokesSystem system(mesh, settings);
  physics::StokesProblem problem;
  problem.viscosity = std::move(viscosity);
  problem.interfacial_tension = std::move(tension);
  problem.body_force = exact.body_force;
  problem.boundary_velocity = [&](const Eigen::Vector3d& x) { return exact.velocity(x, 0); };
  problem.pressure_gauge_node = physics::default_pressure_gauge_node(mesh);
  problem.pressure_gauge_value = exact.pressure(mesh.nodes[problem.pressure_gauge_node], 0);
  const auto result = system.solve(problem);
  ExactRun run;
  run.errors = fem::stokes_errors(mesh, system.dofs(), result.solution, exact.velocity, exact.pressure);
  run.n_dofs = system.dofs().n_dofs();
  return run;
}

/// Moves interior vertices randomly by up to `fraction` of the cell size and
/// puts edge nodes back at edge midpoints: a distorted, straight-sided mesh.
inline void distort_affinely(mesh::Mesh& mesh, double cell_size, double fraction, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const Eigen::Vector3d half(mesh.box.length / 2, mesh.box.height / 2, mesh.box.width / 2);
  for (int i = 0; i < mesh.n_nodes(); ++i) {
    if (!mesh.is_vertex[i]) continue;
    auto& x = mesh.nodes[i];
    const bool interior = (half - x.cwiseAbs()).minCoeff() > 1e-9;
    if (interior) x += fraction * cell_size * Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
  }
  for (const auto& tet : mesh.tets)
    for (int e = 0; e < 6; ++e)
      mesh.nodes[tet[4 + e]] =
          0.5 * (mesh.nodes[tet[mesh::kTetEdges[e][0]]] + mesh.nodes[tet[mesh::kTetEdges[e][1]]]);
}

/// A smooth nonlinear map of [-1,1]^3 onto itself that keeps the box faces
/// planar: every node moves, so interior elements become curved.
inline Eigen::Vector3d curving_map(const Eigen::Vector3d& x, double amplitude) {
  const double s = std::sin(M_PI * (x[0] + 1) / 2) * std::sin(M_PI * (x[1] + 1) / 2) *
                   std::sin(M_PI * (x[2] + 1) / 2);
  return x + amplitude * s * Eigen::Vector3d(1.0, 0.6, -0.8);
}

}  // namespace softflow::test_support
