#include "softflow/physics/stokes/stokes_kernels.hpp"

#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"

namespace softflow::physics {

double add_stokes_tet_matrix(const element::TetNodes& x, const fem::TetTabulation& tab,
                             double eta, TetMatrix& out, PressureMass* scaled_pressure_mass,
                             double pressure_mass_viscosity) {
  const double mass_eta = pressure_mass_viscosity > 0.0 ? pressure_mass_viscosity : eta;
  double volume = 0.0;
  for (int q = 0; q < tab.rule.size(); ++q) {
    const auto map = element::tet_map(x, tab.p2_grad[q]);
    const double w = tab.rule.weights[q] * map.det_jacobian;
    volume += w;
    const Eigen::Matrix<double, 10, 3> g = element::physical_gradients<10>(tab.p2_grad[q], map);
    const auto& psi = tab.p1[q];
    const Eigen::Matrix<double, 10, 10> gg = g * g.transpose();
    // (1) 2 D(v):D(u) = grad v : grad u + grad v : (grad u)^T
    //     for v = N_k e_c, u = N_l e_d: delta_cd gradN_k.gradN_l + d_d N_k d_c N_l.
    for (int k = 0; k < 10; ++k)
      for (int l = 0; l < 10; ++l) {
        const double diag = eta * w * gg(k, l);
        for (int c = 0; c < 3; ++c) {
          out(3 * k + c, 3 * l + c) += diag;
          for (int d = 0; d < 3; ++d) out(3 * k + c, 3 * l + d) += eta * w * g(k, d) * g(l, c);
        }
      }
    // (2) -(psi_i, d_d N_l) in row p_i, column u_{l,d}, and its transpose.
    for (int i = 0; i < 4; ++i)
      for (int l = 0; l < 10; ++l)
        for (int d = 0; d < 3; ++d) {
          const double b = -w * psi[i] * g(l, d);
          out(30 + i, 3 * l + d) += b;
          out(3 * l + d, 30 + i) += b;
        }
    // (3) -(1/eta)(psi_i, psi_j)
    if (scaled_pressure_mass)
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) (*scaled_pressure_mass)(i, j) -= w * psi[i] * psi[j] / mass_eta;
  }
  return volume;
}

void add_surface_tension(const element::TriangleNodes& x, double gamma,
                         TriangleVelocityVector& out) {
  static const element::QuadratureRule rule = element::triangle_rule(5);
  for (int q = 0; q < rule.size(); ++q) {
    const auto s = element::surface_point(x, rule.points[q]);
    const double w = rule.weights[q] * s.area_scale;
    // div_s (N_k e_d) = (grad_s N_k)_d
    for (int k = 0; k < 6; ++k)
      for (int d = 0; d < 3; ++d) out(3 * k + d) -= gamma * w * s.surface_gradients(k, d);
  }
}

TriangleStiffness surface_stiffness(const element::TriangleNodes& x) {
  // Degree 5: exact on flat triangles (degree-2 integrand) and well below
  // discretisation error on the curved ones, as for the tension load.
  static const element::QuadratureRule rule = element::triangle_rule(5);
  TriangleStiffness s = TriangleStiffness::Zero();
  for (int q = 0; q < rule.size(); ++q) {
    const auto p = element::surface_point(x, rule.points[q]);
    s.noalias() += (rule.weights[q] * p.area_scale) * p.surface_gradients *
                   p.surface_gradients.transpose();
  }
  return s;
}

TriangleStiffness surface_mass(const element::TriangleNodes& x) {
  // Degree 5: exact on flat triangles (degree-4 integrand).
  static const element::QuadratureRule rule = element::triangle_rule(5);
  TriangleStiffness m = TriangleStiffness::Zero();
  for (int q = 0; q < rule.size(); ++q) {
    const auto p = element::surface_point(x, rule.points[q]);
    const auto n = element::p2_triangle_values(rule.points[q]);
    const Eigen::Map<const Eigen::Matrix<double, 6, 1>> values(n.data());
    m.noalias() += (rule.weights[q] * p.area_scale) * values * values.transpose();
  }
  return m;
}

}  // namespace softflow::physics
