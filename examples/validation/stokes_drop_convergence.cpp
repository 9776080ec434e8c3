// Validation: one two-phase Stokes solve around a spherical drop, under mesh refinement.
//
//   stokes_drop_convergence > table.csv
//
// Part 1, drop in shear: unit sphere in a box [-3,3]^3 (shape-uniform
// refinement), the exact
// instantaneous field (analysis/theory/drop_in_linear_flow.hpp) on the box
// faces, Gamma = 0.5, lambda = 0.5, 1, 5; L2 errors of velocity and pressure
// (pressure up to a constant) and the error of the area-averaged pressure
// jump (exact: 2 Gamma = 1).
// Part 2, static drop: unit sphere, Gamma = 1, walls at rest in a periodic
// 8^3 cell; the Laplace jump 2 Gamma / R = 2 and the spurious velocity.
// scripts/validation/stokes_drop.py turns the CSV into docs/validation/.
#include <cmath>
#include <cstdio>

#include <petscsys.h>

#include "softflow/analysis/interface_measures.hpp"
#include "softflow/analysis/theory/drop_in_linear_flow.hpp"
#include "softflow/fem/norms.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"

using namespace softflow;
using analysis::theory::DropInLinearFlow;
using Eigen::Vector3d;

namespace {

geometry::ShearCellSpec unit_drop_cell(double side, int equator_nodes, double far_size,
                                       bool periodic, double growth = 0.3) {
  geometry::ShearCellSpec spec;
  spec.box.length = spec.box.height = spec.box.width = side;
  spec.box.periodic_x = spec.box.periodic_z = periodic;
  spec.objects.push_back(geometry::ObjectSpec{});
  spec.sizing.equator_nodes = equator_nodes;
  spec.sizing.far_size = far_size;
  spec.sizing.growth = growth;
  return spec;
}

void drop_in_shear(double lambda, int n) {
  const double gamma = 0.5;
  const double h0 = 2 * M_PI / (n / 2.0);
  const auto exact =
      DropInLinearFlow::simple_shear(DropInLinearFlow::Kind::instantaneous, lambda, 1.0, gamma);
  // Shape-uniform refinement: growth scaled with h0 (see the drop test's note).
  const auto mesh =
      geometry::build_shear_cell(unit_drop_cell(6.0, n, 2.5 * h0, false, 0.3 * 24 / n));
  physics::StokesSystem system(mesh, la::SaddlePointSettings{});
  physics::StokesProblem problem;
  problem.viscosity = {1.0, lambda};
  problem.interfacial_tension = {gamma};
  problem.boundary_velocity = [&](const Vector3d& x) { return exact.velocity(x, false); };
  problem.pressure_gauge_node = physics::default_pressure_gauge_node(mesh);
  problem.pressure_gauge_value = exact.pressure(mesh.nodes[problem.pressure_gauge_node], false);
  const auto result = system.solve(problem);
  const auto e = fem::stokes_errors(
      mesh, system.dofs(), result.solution,
      [&](const Vector3d& x, int r) { return exact.velocity(x, r == 1); },
      [&](const Vector3d& x, int r) { return exact.pressure(x, r == 1); });
  const auto m = analysis::object_measures(mesh, system.dofs(), result.solution);
  std::printf("shear,%g,%d,%.6f,%d,%.6e,%.6e,%.6e,%.6e\n", lambda, n, h0, system.dofs().n_dofs(),
              e.velocity_l2, e.pressure_l2_mean_free, std::abs(m[0].pressure_jump - 2 * gamma),
              analysis::max_velocity(system.dofs(), result.solution));
}

void static_drop(int n) {
  const double h0 = 2 * M_PI / (n / 2.0);
  const auto mesh = geometry::build_shear_cell(unit_drop_cell(8.0, n, 2.0, true));
  physics::StokesSystem system(mesh, la::SaddlePointSettings{});
  physics::StokesProblem problem;
  problem.viscosity = {1.0, 1.0};
  problem.interfacial_tension = {1.0};
  problem.boundary_velocity = [](const Vector3d&) { return Vector3d::Zero(); };
  problem.pressure_gauge_node = physics::default_pressure_gauge_node(mesh);
  const auto result = system.solve(problem);
  const auto m = analysis::object_measures(mesh, system.dofs(), result.solution);
  std::printf("static,1,%d,%.6f,%d,nan,nan,%.6e,%.6e\n", n, h0, system.dofs().n_dofs(),
              std::abs(m[0].pressure_jump - 2.0), analysis::max_velocity(system.dofs(), result.solution));
}

}  // namespace

int main(int argc, char** argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  std::printf("case,lambda,equator_nodes,h0,unknowns,velocity_l2,pressure_l2,jump_error,max_velocity\n");
  for (double lambda : {0.5, 1.0, 5.0})
    for (int n : {24, 36, 48, 64}) drop_in_shear(lambda, n);
  for (int n : {16, 28, 40, 50}) static_drop(n);
  PetscFinalize();
  return 0;
}
