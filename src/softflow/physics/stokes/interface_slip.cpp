#include "softflow/physics/stokes/interface_slip.hpp"

#include <algorithm>
#include <cmath>

#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/fem/tabulation.hpp"
#include "softflow/physics/stokes/stokes_kernels.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"

namespace softflow::physics {

std::vector<Eigen::Vector3d> interface_node_normals(std::span<const InterfaceMesh> surfaces,
                                                    const mesh::Mesh& geometry) {
  std::vector<Eigen::Vector3d> out(geometry.n_nodes(), Eigen::Vector3d::Zero());
  for (const auto& s : surfaces) {
    const auto normals = node_normals(s, interface_positions(s, geometry));
    for (int i = 0; i < s.n_nodes(); ++i) out[s.volume_node[i]] = normals[i];
  }
  return out;
}

std::vector<double> interface_node_scale(const mesh::Mesh& geometry) {
  std::vector<double> scale(geometry.n_nodes(), 0.0);
  for (const auto& tri : geometry.interface_faces) {
    const auto m = surface_mass(fem::triangle_nodes(geometry, tri));
    for (int a = 0; a < 6; ++a) scale[tri[a]] += m(a, a);
  }
  return scale;
}

bool dissipation_is_negative(const SlipMeasures& m) {
  return m.dissipation < -1e-9 * m.absolute_power;
}

SlipNodePreconditioner slip_node_preconditioner(const fem::DofMap& dofs, const double* diagonal,
                                                int first_row, int node, int object,
                                                const Eigen::Vector3d& normal, double scale,
                                                double alpha) {
  double a_m = 0.0, a_d = 0.0;
  for (int c = 0; c < 3; ++c) {
    a_m += diagonal[dofs.dof(kVelocityField, node, 0, c) - first_row] / 3.0;
    a_d += diagonal[dofs.dof(kVelocityField, node, object, c) - first_row] / 3.0;
  }
  const double penalty = 0.01 * (a_m + a_d);
  const double compliance = (a_m + a_d) / (a_m * a_d + penalty * (a_m + a_d));
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  SlipNodePreconditioner p;
  p.jump_penalty << penalty * identity, -penalty * identity, -penalty * identity,
      penalty * identity;
  const double w = std::isinf(alpha) ? 0.0 : 1.0 / (1.0 + alpha);
  const Eigen::Matrix3d row_weight =
      normal * normal.transpose() + w * (identity - normal * normal.transpose());
  p.schur_estimate = (-scale * scale * compliance) * row_weight;
  return p;
}

double largest_resolved_slip(int equator_nodes) {
  const double refinement = equator_nodes / 16.0;
  return 100.0 * refinement * refinement * refinement * refinement;
}

Eigen::Vector3d slip_traction(const std::array<double, 6>& shape, const Eigen::Vector3d& normal,
                              const TriangleNormals& nodal, const Eigen::Matrix<double, 3, 6>& lambda) {
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (int a = 0; a < 6; ++a) {
    const double normal_part = nodal[a].dot(lambda.col(a));
    t += shape[a] * (normal_part * normal + (lambda.col(a) - normal_part * nodal[a]));
  }
  return t;
}

Eigen::Matrix<double, 18, 54> slip_constraint_block(const Eigen::Matrix<double, 18, 18>& coupling,
                                                   const Eigen::Matrix<double, 6, 6>& mass,
                                                   const TriangleNormals& nodal, double alpha) {
  // Row weights per node: D_a = n_a n_a + w T_a with w = 1 / (1 + alpha), a
  // change of each node's three rows that leaves the solution as it is but
  // keeps them of one size as alpha grows; alpha = inf gives free slip
  // (T lambda = 0) exactly.
  const bool free_slip = std::isinf(alpha);
  const double w = free_slip ? 0.0 : 1.0 / (1.0 + alpha);
  const double alpha_w = free_slip ? 1.0 : alpha * w;
  auto tangential = [&](int a) -> Eigen::Matrix3d {
    return Eigen::Matrix3d::Identity() - nodal[a] * nodal[a].transpose();
  };
  Eigen::Matrix<double, 18, 54> block;
  for (int a = 0; a < 6; ++a) {
    const Eigen::Matrix3d ta = tangential(a);
    const Eigen::Matrix3d row_weight = nodal[a] * nodal[a].transpose() + w * ta;
    for (int b = 0; b < 6; ++b) {
      // The coupling's transpose: lambda_a's rows against v_b.
      const Eigen::Matrix3d jump = row_weight * coupling.block<3, 3>(3 * b, 3 * a).transpose();
      block.block<3, 3>(3 * a, 3 * b) = jump;          // u_m
      block.block<3, 3>(3 * a, 18 + 3 * b) = -jump;    // u_d
      block.block<3, 3>(3 * a, 36 + 3 * b) =           // lambda
          (-alpha_w * mass(a, b)) * ta * tangential(b);
    }
  }
  return block;
}

Eigen::Matrix<double, 18, 18> slip_coupling_matrix(const element::TriangleNodes& x,
                                                   const TriangleNormals& nodal) {
  // Degree 5 as surface_mass: exact on flat triangles for the mass part.
  static const element::QuadratureRule rule = element::triangle_rule(5);
  Eigen::Matrix<double, 18, 18> c = Eigen::Matrix<double, 18, 18>::Zero();
  for (int q = 0; q < rule.size(); ++q) {
    const auto p = element::surface_point(x, rule.points[q]);
    const auto n = element::p2_triangle_values(rule.points[q]);
    const double w = rule.weights[q] * p.area_scale;
    for (int a = 0; a < 6; ++a) {
      // lambda_a -> traction: n n_a^T + T_a = I + (n - n_a) n_a^T.
      const Eigen::Matrix3d map =
          Eigen::Matrix3d::Identity() + (p.normal - nodal[a]) * nodal[a].transpose();
      for (int b = 0; b < 6; ++b) c.block<3, 3>(3 * b, 3 * a) += (w * n[a] * n[b]) * map;
    }
  }
  return c;
}

std::vector<SlipMeasures> slip_measures(const mesh::Mesh& geometry, const fem::DofMap& dofs,
                                        std::span<const Eigen::Vector3d> node_normals,
                                        std::span<const double> solution) {
  return slip_measures(geometry, dofs, node_normals,
                       [solution](int dof) { return solution[dof]; });
}

std::vector<SlipMeasures> slip_measures(const mesh::Mesh& geometry, const fem::DofMap& dofs,
                                        std::span<const Eigen::Vector3d> node_normals,
                                        const std::function<double(int dof)>& value) {
  std::vector<SlipMeasures> out(geometry.n_objects);
  std::vector<double> max_nodal(geometry.n_objects, 0.0);
  static const element::QuadratureRule rule = element::triangle_rule(5);
  for (std::size_t f = 0; f < geometry.interface_faces.size(); ++f) {
    const auto& tri = geometry.interface_faces[f];
    const int object = geometry.interface_object[f];
    auto& m = out[object - 1];
    // Jump u_m - u_d, multipliers and normals at the triangle's 6 nodes.
    Eigen::Matrix<double, 3, 6> jump, lambda;
    TriangleNormals nodal;
    for (int a = 0; a < 6; ++a) {
      nodal[a] = node_normals[tri[a]];
      for (int c = 0; c < 3; ++c) {
        jump(c, a) = value(dofs.dof(kVelocityField, tri[a], 0, c)) -
                     value(dofs.dof(kVelocityField, tri[a], object, c));
        lambda(c, a) = value(dofs.dof(kMultiplierField, tri[a], object, c));
      }
    }
    const auto x = fem::triangle_nodes(geometry, tri);
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(x, rule.points[q]);
      const auto n = element::p2_triangle_values(rule.points[q]);
      const Eigen::Map<const Eigen::Matrix<double, 6, 1>> values(n.data());
      const Eigen::Vector3d du = jump * values;
      const Eigen::Vector3d l = slip_traction(n, p.normal, nodal, lambda);
      const double w = rule.weights[q] * p.area_scale;
      m.area += w;
      m.mean_slip_speed += w * (du - du.dot(p.normal) * p.normal).norm();
      m.dissipation += w * l.dot(du);
      m.absolute_power += w * std::abs(l.dot(du));
    }
    for (int a = 0; a < 6; ++a) {
      // The nodal jump: its normal part vanishes in the weak sense only,
      // to the discretisation's order.
      max_nodal[object - 1] = std::max(max_nodal[object - 1], jump.col(a).norm());
    }
  }
  for (int k = 0; k < geometry.n_objects; ++k) {
    if (out[k].area > 0.0) out[k].mean_slip_speed /= out[k].area;
    out[k].max_slip_speed = max_nodal[k];
  }
  return out;
}

}  // namespace softflow::physics
