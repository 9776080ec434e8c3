#include "softflow/analysis/interface_measures.hpp"

#include <algorithm>
#include <cmath>

#include "softflow/element/quadrature.hpp"
#include "softflow/fem/tabulation.hpp"

namespace softflow::analysis {

std::vector<ObjectMeasures> object_measures(const mesh::Mesh& mesh, const fem::DofMap& dofs,
                                            const std::vector<double>& solution) {
  std::vector<ObjectMeasures> m(mesh.n_objects);
  for (int k = 0; k < mesh.n_objects; ++k) m[k].object = k + 1;

  static const fem::TetTabulation tab(4);
  const int velocity = dofs.field_index("velocity"), pressure = dofs.field_index("pressure");
  for (int t = 0; t < mesh.n_tets(); ++t) {
    const int region = mesh.tet_region[t];
    if (region == 0) continue;
    const auto x = fem::tet_nodes(mesh, t);
    for (int q = 0; q < tab.rule.size(); ++q) {
      const double w = tab.rule.weights[q] * element::tet_map(x, tab.p2_grad[q]).det_jacobian;
      Eigen::Vector3d xq = Eigen::Vector3d::Zero();
      for (int n = 0; n < 10; ++n) xq += tab.p2[q][n] * x.col(n);
      m[region - 1].volume += w;
      m[region - 1].centre += w * xq;
    }
  }

  static const element::QuadratureRule rule = element::triangle_rule(5);
  for (std::size_t f = 0; f < mesh.interface_faces.size(); ++f) {
    const auto& tri = mesh.interface_faces[f];
    const int object = mesh.interface_object[f];
    ObjectMeasures& om = m[object - 1];
    const auto x = fem::triangle_nodes(mesh, tri);
    double jump[3];
    for (int v = 0; v < 3; ++v)
      jump[v] = solution[dofs.dof(pressure, tri[v], object)] - solution[dofs.dof(pressure, tri[v], 0)];
    for (int q = 0; q < rule.size(); ++q) {
      const auto s = element::surface_point(x, rule.points[q]);
      const double w = rule.weights[q] * s.area_scale;
      const auto l = element::p1_triangle_values(rule.points[q]);
      const auto n2 = element::p2_triangle_values(rule.points[q]);
      om.area += w;
      om.pressure_jump += w * (l[0] * jump[0] + l[1] * jump[1] + l[2] * jump[2]);
      for (int k = 0; k < 6; ++k) {
        // With slip the two copies differ tangentially: their mean (one dof
        // with a continuous velocity).
        const int vm = dofs.dof(velocity, tri[k], 0), vd = dofs.dof(velocity, tri[k], object);
        om.mean_interface_velocity +=
            (0.5 * w * n2[k]) * Eigen::Vector3d(solution[vm] + solution[vd], solution[vm + 1] + solution[vd + 1],
                                                solution[vm + 2] + solution[vd + 2]);
      }
    }
  }
  for (auto& om : m) {
    if (om.volume > 0) om.centre /= om.volume;
    if (om.area > 0) {
      om.pressure_jump /= om.area;
      om.mean_interface_velocity /= om.area;
    }
  }
  return m;
}

double max_velocity(const fem::DofMap& dofs, const std::vector<double>& solution) {
  // A field's components are contiguous (fem::DofMap): (x, y, z) triples.
  const int velocity = dofs.field_index("velocity");
  double u = 0.0;
  for (int i = 0; i < dofs.n_dofs();) {
    if (dofs.field_of(i) != velocity) {
      ++i;
      continue;
    }
    u = std::max(u, std::hypot(solution[i], solution[i + 1], solution[i + 2]));
    i += 3;
  }
  return u;
}

}  // namespace softflow::analysis
