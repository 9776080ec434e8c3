#include "softflow/physics/interface/interface_mesh.hpp"

#include <unordered_map>

#include "softflow/element/isoparametric.hpp"
#include "softflow/element/quadrature.hpp"

namespace softflow::physics {

InterfaceMesh extract_interface(const mesh::Mesh& mesh, int object) {
  InterfaceMesh s;
  s.object = object;
  std::unordered_map<int, int> local;
  for (std::size_t f = 0; f < mesh.interface_faces.size(); ++f) {
    if (mesh.interface_object[f] != object) continue;
    std::array<int, 6> tri{};
    for (int k = 0; k < 6; ++k) {
      const int node = mesh.interface_faces[f][k];
      auto [it, inserted] = local.try_emplace(node, s.n_nodes());
      if (inserted) s.volume_node.push_back(node);
      tri[k] = it->second;
    }
    s.triangles.push_back(tri);
  }
  return s;
}

std::vector<Vec3> interface_positions(const InterfaceMesh& s, const mesh::Mesh& mesh) {
  std::vector<Vec3> x(s.n_nodes());
  for (int i = 0; i < s.n_nodes(); ++i) x[i] = mesh.nodes[s.volume_node[i]];
  return x;
}

namespace {
element::TriangleNodes triangle_at(const std::array<int, 6>& tri, const std::vector<Vec3>& x) {
  element::TriangleNodes nodes;
  for (int k = 0; k < 6; ++k) nodes.col(k) = x[tri[k]];
  return nodes;
}
}  // namespace

SurfaceIntegrals surface_integrals(const InterfaceMesh& s, const std::vector<Vec3>& x) {
  // Degree 7: the integrands are rational on curved P2 triangles; this keeps
  // the volume error far below the geometric one.
  static const element::QuadratureRule rule = element::triangle_rule(7);
  SurfaceIntegrals r;
  for (const auto& tri : s.triangles) {
    const auto nodes = triangle_at(tri, x);
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(nodes, rule.points[q]);
      const double w = rule.weights[q] * p.area_scale;
      r.area += w;
      r.volume += w * p.normal.dot(p.position) / 3.0;                   // eq. 2.53
      r.first_moment += w * p.normal * p.position.squaredNorm() / 2.0;  // eq. 2.54
    }
  }
  return r;
}

std::vector<double> triangle_areas(const InterfaceMesh& s, const std::vector<Vec3>& x) {
  static const element::QuadratureRule rule = element::triangle_rule(5);
  std::vector<double> areas;
  areas.reserve(s.triangles.size());
  for (const auto& tri : s.triangles) {
    const auto nodes = triangle_at(tri, x);
    double a = 0.0;
    for (int q = 0; q < rule.size(); ++q)
      a += rule.weights[q] * element::surface_point(nodes, rule.points[q]).area_scale;
    areas.push_back(a);
  }
  return areas;
}

std::vector<Vec3> node_normals(const InterfaceMesh& s, const std::vector<Vec3>& x) {
  // Reference coordinates of the 6 triangle nodes: vertices, then the
  // midpoints of edges (0,1), (1,2), (2,0).
  static const std::array<Vec3, 6> kNodeXi = {Vec3(0, 0, 0),     Vec3(1, 0, 0),
                                              Vec3(0, 1, 0),     Vec3(0.5, 0, 0),
                                              Vec3(0.5, 0.5, 0), Vec3(0, 0.5, 0)};
  const auto areas = triangle_areas(s, x);
  std::vector<Vec3> normal(s.n_nodes(), Vec3::Zero());
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const auto nodes = triangle_at(s.triangles[t], x);
    for (int k = 0; k < 6; ++k)
      normal[s.triangles[t][k]] += areas[t] * element::surface_point(nodes, kNodeXi[k]).normal;
  }
  for (auto& n : normal) n.normalize();
  return normal;
}

}  // namespace softflow::physics
