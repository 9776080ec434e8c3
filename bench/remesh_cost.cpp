// Benchmark: the cost of a remesh (gmsh around the current interface, then
// the transfer of a run's fields) against a Stokes step on the same mesh.
//
//   remesh_cost [equator_nodes] [strain]
//
// The cell of examples/elastic_particle.toml (box 30 R, one unit object at
// the centre, far size 3.2, growth 0.4): meshed, its object stretched along
// x by `strain` (a smooth, volume-preserving-to-first-order deformation that
// vanishes 2.2 R from the centre, as test_remesh.cpp's) to degrade the
// elements as a run would, then remeshed. Prints one JSON line: nodes and
// worst quality before/after, remesh (gmsh) and transfer seconds (velocity
// 3 x P2, pressure P1 per region, a log-conformation 6 x P1 per region and
// the mesh velocity), the relative change of the object's volume, and the
// cold (pattern, assembly, LU) and warm (reused factors) Stokes solves on
// the new mesh: after a remesh the next step pays the cold one.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include <fmt/format.h>
#include <petscsys.h>

#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/fem/mesh_transfer.hpp"
#include "softflow/fem/space.hpp"
#include "softflow/geometry/remesh.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"

using namespace softflow;
using Eigen::Vector3d;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double object_volume(const mesh::Mesh& m) {
  const auto rule = element::tetrahedron_rule(3);
  double volume = 0.0;
  for (int t = 0; t < m.n_tets(); ++t) {
    if (m.tet_region[t] != 1) continue;
    Eigen::Matrix<double, 3, 10> x;
    for (int k = 0; k < 10; ++k) x.col(k) = m.nodes[m.tets[t][k]];
    for (int q = 0; q < rule.size(); ++q)
      volume += rule.weights[q] * (x * element::p2_tet_gradients(rule.points[q])).determinant();
  }
  return volume;
}

}  // namespace

int main(int argc, char** argv) {
  const int equator_nodes = argc > 1 ? std::stoi(argv[1]) : 28;
  const double strain = argc > 2 ? std::stod(argv[2]) : 0.45;
  int petsc_argc = 1;
  if (PetscInitialize(&petsc_argc, &argv, nullptr, nullptr) != 0) return 1;
  {
    geometry::ShearCellSpec spec;
    spec.box.length = spec.box.height = spec.box.width = 30.0;
    spec.objects.push_back(geometry::ObjectSpec{});
    spec.sizing.equator_nodes = equator_nodes;
    spec.sizing.far_size = 3.2;
    spec.sizing.growth = 0.4;
    mesh::Mesh before = geometry::build_shear_cell(spec);
    for (auto& x : before.nodes) {
      const double s = x.norm() / 2.2;
      const double bump = s < 1.0 ? std::pow(1.0 - s * s, 2) : 0.0;
      x += strain * bump * Vector3d(x.x(), -0.5 * x.y(), -0.5 * x.z());
    }

    auto start = Clock::now();
    const auto r = geometry::remesh(spec, before);
    const double remesh_seconds = seconds_since(start);

    start = Clock::now();
    const fem::MeshTransfer transfer(before, r.mesh, r.new_node_of_old);
    double transferred = 0.0;  // keeps the results alive
    for (auto [degree, continuity, components] :
         {std::tuple{2, fem::Continuity::continuous, 3}, std::tuple{1, fem::Continuity::per_region, 1},
          std::tuple{1, fem::Continuity::per_region, 6}}) {
      const fem::Space old_space(before, degree, continuity), new_space(r.mesh, degree, continuity);
      std::vector<double> values(static_cast<std::size_t>(old_space.n_dofs()) * components, 1.0);
      transferred += transfer.transfer(old_space, new_space, components, values).back();
    }
    transferred += transfer.transfer_nodal(before.nodes).back().x();
    const double transfer_seconds = seconds_since(start);

    const double v0 = object_volume(before), v1 = object_volume(r.mesh);

    la::SaddlePointSettings settings;
    physics::StokesProblem problem;
    problem.viscosity = {1.0, 1.0};
    problem.interfacial_tension = {10.0};
    problem.boundary_velocity = [](const Vector3d& x) { return Vector3d(x.y(), 0, 0); };
    problem.pressure_gauge_node = physics::default_pressure_gauge_node(r.mesh);
    physics::StokesSystem system(r.mesh, settings);
    start = Clock::now();
    system.solve(problem);
    const double cold = seconds_since(start);
    start = Clock::now();
    system.solve(problem);
    const double warm = seconds_since(start);

    fmt::print(
        "{{\"equator_nodes\": {}, \"strain\": {}, \"nodes_before\": {}, \"nodes_after\": {}, "
        "\"quality_before\": {:.4f}, \"quality_after\": {:.4f}, \"remesh_seconds\": {:.3f}, "
        "\"transfer_seconds\": {:.3f}, \"volume_change\": {:.3e}, \"largest_extrapolation\": {:.3e}, "
        "\"stokes_cold_seconds\": {:.3f}, \"stokes_warm_seconds\": {:.3f}, \"check\": {}}}\n",
        equator_nodes, strain, r.report.nodes_before, r.report.nodes_after, r.report.quality_before,
        r.report.quality_after, remesh_seconds, transfer_seconds, (v1 - v0) / v0, transfer.largest_extrapolation(),
        cold, warm, transferred);
  }
  PetscFinalize();
  return 0;
}
