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

std::vector<SlipMeasures> slip_measures(const mesh::Mesh& geometry, const fem::DofMap& dofs,
                                        std::span<const double> solution) {
  return slip_measures(geometry, dofs, [solution](int dof) { return solution[dof]; });
}

std::vector<SlipMeasures> slip_measures(const mesh::Mesh& geometry, const fem::DofMap& dofs,
                                        const std::function<double(int dof)>& value) {
  std::vector<SlipMeasures> out(geometry.n_objects);
  std::vector<double> max_nodal(geometry.n_objects, 0.0);
  static const element::QuadratureRule rule = element::triangle_rule(5);
  for (std::size_t f = 0; f < geometry.interface_faces.size(); ++f) {
    const auto& tri = geometry.interface_faces[f];
    const int object = geometry.interface_object[f];
    auto& m = out[object - 1];
    // Jump u_m - u_d and multiplier at the triangle's 6 nodes.
    Eigen::Matrix<double, 3, 6> jump, lambda;
    for (int a = 0; a < 6; ++a)
      for (int c = 0; c < 3; ++c) {
        jump(c, a) = value(dofs.dof(kVelocityField, tri[a], 0, c)) -
                     value(dofs.dof(kVelocityField, tri[a], object, c));
        lambda(c, a) = value(dofs.dof(kMultiplierField, tri[a], object, c));
      }
    const auto x = fem::triangle_nodes(geometry, tri);
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(x, rule.points[q]);
      const auto n = element::p2_triangle_values(rule.points[q]);
      const Eigen::Map<const Eigen::Matrix<double, 6, 1>> values(n.data());
      const Eigen::Vector3d du = jump * values, l = lambda * values;
      const double w = rule.weights[q] * p.area_scale;
      m.area += w;
      m.mean_slip_speed += w * (du - du.dot(p.normal) * p.normal).norm();
      m.dissipation += w * l.dot(du);
    }
    for (int a = 0; a < 6; ++a) {
      // The nodal tangential jump: the normal part vanishes at nodes.
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
