#include "support/verification/slip_drop.hpp"

#include <cmath>
#include <vector>

#include "softflow/analysis/theory/drop_in_linear_flow.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/fem/norms.hpp"
#include "softflow/fem/tabulation.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/physics/stokes/interface_slip.hpp"
#include "softflow/physics/stokes/stokes_kernels.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"

namespace softflow::verification {

namespace {

using analysis::theory::DropInLinearFlow;
using Eigen::Vector3d;

// The discrete energy terms of one solution, from the element matrices the
// system assembles (degree-5 rule, as StokesSystem):
//   viscous dissipation  sum_e u_e^T A_e u_e,
//   boundary work        sum_e g_e^T K_e x_e, g = u on boundary velocity dofs, 0 elsewhere
//                        (the reactions of the Dirichlet rows times the wall velocities),
//   tension work         the tension load on the copy that carries it times that velocity.
// Testing the momentum rows with v = u - g gives
//   viscous dissipation + slip dissipation = boundary work + tension work
// up to the solver tolerance (the continuity rows make b(p, u) vanish).
void energy_terms(const mesh::Mesh& mesh, const physics::StokesSystem& system,
                  const std::vector<double>& x, double lambda, double gamma, SlipDropResult& r) {
  const auto& dofs = system.dofs();
  std::vector<char> on_boundary(dofs.n_dofs(), 0);
  for (const auto& face : mesh.boundary_faces)
    for (int node : face)
      for (int c = 0; c < 3; ++c) on_boundary[dofs.dof(physics::kVelocityField, node, 0, c)] = 1;
  const fem::TetTabulation tab(5);
  for (int t = 0; t < mesh.n_tets(); ++t) {
    physics::TetMatrix ke = physics::TetMatrix::Zero();
    physics::add_stokes_tet_matrix(fem::tet_nodes(mesh, t), tab,
                                   mesh.tet_region[t] == 0 ? 1.0 : lambda, ke);
    const auto d = dofs.element_dofs(t);
    physics::TetVector xe, ge = physics::TetVector::Zero();
    for (int i = 0; i < 34; ++i) {
      xe(i) = x[d[i]];
      if (i < 30 && on_boundary[d[i]]) ge(i) = x[d[i]];
    }
    r.viscous_dissipation += xe.head<30>().dot(ke.topLeftCorner<30, 30>() * xe.head<30>());
    r.boundary_work += ge.dot(ke * xe);
  }
  for (std::size_t f = 0; f < mesh.interface_faces.size(); ++f) {
    const auto& tri = mesh.interface_faces[f];
    physics::TriangleVelocityVector load = physics::TriangleVelocityVector::Zero();
    physics::add_surface_tension(fem::triangle_nodes(mesh, tri), gamma, load);
    const int side = system.interface_slip() ? mesh.interface_object[f] : 0;
    for (int k = 0; k < 6; ++k)
      for (int c = 0; c < 3; ++c)
        r.tension_work += load(3 * k + c) * x[dofs.dof(physics::kVelocityField, tri[k], side, c)];
  }
}

}  // namespace

SlipDropResult slip_drop_in_shear(double lambda, double alpha, double gamma, int equator_nodes,
                                  bool interface_slip, bool iterative) {
  const double h0 = 2 * M_PI / (equator_nodes / 2.0);
  const auto exact = DropInLinearFlow::simple_shear(DropInLinearFlow::Kind::instantaneous, lambda,
                                                    1.0, gamma, alpha);
  geometry::ShearCellSpec spec;
  spec.box.length = spec.box.height = spec.box.width = 6.0;
  spec.box.periodic_x = spec.box.periodic_z = false;
  spec.objects.push_back(geometry::ObjectSpec{});
  spec.sizing.equator_nodes = equator_nodes;
  spec.sizing.far_size = 2.5 * h0;
  spec.sizing.growth = 0.3 * 24 / equator_nodes;
  const auto mesh = geometry::build_shear_cell(spec);

  la::SaddlePointSettings settings;
  if (iterative) {
    settings.method = la::SaddlePointMethod::iterative;
    settings.rtol = 1e-10;
  }
  physics::StokesSystem system(mesh, settings, interface_slip);
  physics::StokesProblem problem;
  problem.viscosity = {1.0, lambda};
  problem.interfacial_tension = {gamma};
  if (interface_slip) problem.slip.coefficient = {alpha};  // R = eta_m = 1
  problem.boundary_velocity = [&](const Vector3d& x) { return exact.velocity(x, false); };
  problem.pressure_gauge_node = physics::default_pressure_gauge_node(mesh);
  problem.pressure_gauge_value = exact.pressure(mesh.nodes[problem.pressure_gauge_node], false);
  const auto result = system.solve(problem);
  const auto& x = result.solution;

  SlipDropResult r;
  r.equator_nodes = equator_nodes;
  r.h0 = h0;
  r.unknowns = system.dofs().n_dofs();
  r.iterations = result.solve.iterations;
  const auto errors = fem::stokes_errors(
      mesh, system.dofs(), x,
      [&](const Vector3d& p, int region) { return exact.velocity(p, region == 1); },
      [&](const Vector3d& p, int region) { return exact.pressure(p, region == 1); });
  r.velocity_l2 = errors.velocity_l2;
  r.pressure_l2 = errors.pressure_l2_mean_free;
  energy_terms(mesh, system, x, lambda, gamma, r);
  if (!interface_slip) return r;

  // Interface integrals: the jump against the exact one (at the points
  // projected onto the exact sphere r = 1) and the Navier law's dissipation
  // alpha |(I - nn) lambda_h|^2; the exact slip dissipation in closed form.
  const auto& dofs = system.dofs();
  const auto normals = system.slip_node_normals(mesh);
  static const element::QuadratureRule rule = element::triangle_rule(8);
  double jump2 = 0.0, exact2 = 0.0;
  for (const auto& tri : mesh.interface_faces) {
    const auto xt = fem::triangle_nodes(mesh, tri);
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(xt, rule.points[q]);
      const auto n = element::p2_triangle_values(rule.points[q]);
      Vector3d jump = Vector3d::Zero();
      Eigen::Matrix<double, 3, 6> multipliers;
      physics::TriangleNormals nodal;
      for (int a = 0; a < 6; ++a) {
        nodal[a] = normals[tri[a]];
        for (int c = 0; c < 3; ++c) {
          jump(c) += n[a] * (x[dofs.dof(physics::kVelocityField, tri[a], 0, c)] -
                             x[dofs.dof(physics::kVelocityField, tri[a], 1, c)]);
          multipliers(c, a) = x[dofs.dof(physics::kMultiplierField, tri[a], 1, c)];
        }
      }
      const Vector3d lam = physics::slip_traction(n, p.normal, nodal, multipliers);
      const Vector3d on_sphere = p.position.normalized();
      const Vector3d exact_jump = exact.velocity(on_sphere, false) - exact.velocity(on_sphere, true);
      const double w = rule.weights[q] * p.area_scale;
      jump2 += w * (jump - exact_jump).squaredNorm();
      exact2 += w * exact_jump.squaredNorm();
      r.navier_dissipation += w * alpha * (lam - lam.dot(p.normal) * p.normal).squaredNorm();
    }
  }
  r.exact_slip_dissipation = exact.slip_dissipation();
  r.jump_l2 = std::sqrt(jump2);
  r.exact_jump_l2 = std::sqrt(exact2);
  r.slip_dissipation = physics::slip_measures(mesh, dofs, normals, x)[0].dissipation;
  return r;
}

}  // namespace softflow::verification
