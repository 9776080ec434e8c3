#include "softflow/geometry/interface_surface.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <utility>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <gmsh.h>

#include "softflow/common/error.hpp"
#include "softflow/element/isoparametric.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/geometry/gmsh_mesh.hpp"
#include "softflow/geometry/point_tree.hpp"
#include "softflow/mesh/quality.hpp"

namespace softflow::geometry {

using Eigen::Vector3d;

namespace {

using Edge = std::pair<int, int>;
Edge edge_key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

element::TriangleNodes as_columns(const std::array<Vector3d, 6>& x) {
  element::TriangleNodes nodes;
  for (int k = 0; k < 6; ++k) nodes.col(k) = x[k];
  return nodes;
}

const element::QuadratureRule& volume_rule() {
  static const element::QuadratureRule rule =
      element::triangle_rule(4);  // x.(x_xi0 x x_xi1): degree 4
  return rule;
}

// Calls visit(point, weight) at each point of `rule` on triangle t of s.
template <class Visit>
void integrate_on_triangle(const InterfaceSurface& s, int t, const element::QuadratureRule& rule,
                           Visit&& visit) {
  const auto nodes = as_columns(s.triangle_nodes(t));
  for (int q = 0; q < rule.size(); ++q)
    visit(element::surface_point(nodes, rule.points[q]), rule.weights[q]);
}

// ---------------------------------------------------------------------------
// The closest point of a curved P2 surface
// ---------------------------------------------------------------------------

struct SurfaceHit {
  Vector3d position = Vector3d::Zero();
  Vector3d normal = Vector3d::Zero();  ///< unit, outward
  double distance = std::numeric_limits<double>::infinity();
  InterfaceSurface::Origin origin;  ///< the triangle and its reference coordinates
};

// The closest point to p of one curved P2 triangle: Gauss-Newton on
// |x(xi) - p|^2 from the straight triangle's closest point, each step
// clamped to the reference triangle. A few iterations: the triangles are
// nearly flat on the scale of an element.
SurfaceHit closest_on_curved_triangle(const element::TriangleNodes& nodes, const Vector3d& p) {
  Vector3d xi(1.0 / 3.0, 1.0 / 3.0, 0.0);
  const auto clamp = [](Vector3d& x) {
    x[0] = std::max(0.0, x[0]);
    x[1] = std::max(0.0, x[1]);
    if (const double s = x[0] + x[1]; s > 1.0) {
      x[0] /= s;
      x[1] /= s;
    }
  };
  for (int iteration = 0; iteration < 12; ++iteration) {
    const auto gradients = element::p2_triangle_gradients(xi);
    const auto values = element::p2_triangle_values(xi);
    Vector3d x = Vector3d::Zero();
    for (int k = 0; k < 6; ++k) x += values[k] * nodes.col(k);
    const Eigen::Matrix<double, 3, 2> jacobian = nodes * gradients;
    const Eigen::Vector2d step =
        (jacobian.transpose() * jacobian).ldlt().solve(-jacobian.transpose() * (x - p));
    const Vector3d before = xi;
    xi.head<2>() += step;
    clamp(xi);
    if ((xi - before).norm() < 1e-14) break;
  }
  const element::SurfacePoint point = element::surface_point(nodes, xi);
  return {point.position, point.normal, (point.position - p).norm(), {-1, xi.head<2>()}};
}

// Closest points of one closed P2 surface: the triangles around the P2 node
// nearest the query and their neighbours are tried (the query points lie on
// or within a sag of the surface, so the closest triangle is among them).
class SurfaceProjector {
 public:
  explicit SurfaceProjector(const InterfaceSurface& s) {
    std::vector<Vector3d> points;
    std::map<Edge, int> edge_point;
    for (std::size_t t = 0; t < s.triangles.size(); ++t) {
      nodes_.push_back(as_columns(s.triangle_nodes(static_cast<int>(t))));
      std::array<int, 6> ids{};
      for (int k = 0; k < 3; ++k) ids[k] = s.triangles[t][k];
      for (int k = 0; k < 3; ++k) {
        const auto& e = mesh::kTriangleEdges[k];
        const auto [it, added] =
            edge_point.emplace(edge_key(s.triangles[t][e[0]], s.triangles[t][e[1]]),
                               static_cast<int>(s.vertices.size() + edge_point.size()));
        ids[3 + k] = it->second;
      }
      point_ids_.push_back(ids);
    }
    points.resize(s.vertices.size() + edge_point.size());
    around_.resize(points.size());
    for (std::size_t t = 0; t < point_ids_.size(); ++t)
      for (int k = 0; k < 6; ++k) {
        points[point_ids_[t][k]] = nodes_[t].col(k);
        around_[point_ids_[t][k]].push_back(static_cast<int>(t));
      }
    tree_ = std::make_unique<detail::PointTree>(std::move(points));
  }

  [[nodiscard]] SurfaceHit closest(const Vector3d& p) const {
    const int nearest = tree_->nearest(p);
    std::vector<int> candidates;
    for (int t : around_[nearest])
      for (int id : point_ids_[t])
        candidates.insert(candidates.end(), around_[id].begin(), around_[id].end());
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    SurfaceHit best;
    for (int t : candidates) {
      SurfaceHit hit = closest_on_curved_triangle(nodes_[t], p);
      hit.origin.triangle = t;
      if (hit.distance < best.distance) best = hit;
    }
    return best;
  }

 private:
  std::vector<element::TriangleNodes> nodes_;
  std::vector<std::array<int, 6>>
      point_ids_;                         // per triangle: its 6 nodes' indices among the points
  std::vector<std::vector<int>> around_;  // per point: the triangles that have it
  std::unique_ptr<detail::PointTree> tree_;
};

// ---------------------------------------------------------------------------
// gmsh: a fresh straight triangulation of the surface
// ---------------------------------------------------------------------------

struct StraightTriangulation {
  std::vector<Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
};

// gmsh's frontal-Delaunay on the surface as a discrete entity, after
// classifySurfaces/createGeometry have cut it into patches that each have
// one parametrisation (two for a sphere-like surface). Each P2 triangle is
// handed over as its four straight sub-triangles through its edge nodes:
// the parametrised surface then lies within a quarter of the P2 surface's
// sag of it.
StraightTriangulation mesh_surface(const InterfaceSurface& s,
                                   const std::function<double(const Vector3d&)>& size) {
  StraightTriangulation out;
  detail::GmshSession session;
  session.run("resampling an interface", [&] {
    gmsh::model::addDiscreteEntity(2, 1);
    std::vector<std::size_t> tags;
    std::vector<double> coordinates;
    const auto add_node = [&](const Vector3d& x) {
      tags.push_back(tags.size() + 1);
      coordinates.insert(coordinates.end(), {x.x(), x.y(), x.z()});
      return tags.back();
    };
    for (const Vector3d& x : s.vertices) add_node(x);
    std::map<Edge, std::size_t> edge_tag;
    std::vector<std::size_t> triangle_nodes;
    for (std::size_t t = 0; t < s.triangles.size(); ++t) {
      const auto& tri = s.triangles[t];
      std::array<std::size_t, 6> n{};
      for (int k = 0; k < 3; ++k) n[k] = static_cast<std::size_t>(tri[k]) + 1;
      for (int k = 0; k < 3; ++k) {
        const auto& e = mesh::kTriangleEdges[k];
        const Edge key = edge_key(tri[e[0]], tri[e[1]]);
        auto it = edge_tag.find(key);
        if (it == edge_tag.end()) it = edge_tag.emplace(key, add_node(s.edge_nodes[t][k])).first;
        n[3 + k] = it->second;
      }
      // corners 0 1 2, edge nodes 3 (01), 4 (12), 5 (20)
      for (const std::array<int, 3>& sub :
           {std::array<int, 3>{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}})
        for (int k : sub) triangle_nodes.push_back(n[k]);
    }
    gmsh::model::mesh::addNodes(2, 1, tags, coordinates);
    std::vector<std::size_t> element_tags(triangle_nodes.size() / 3);
    for (std::size_t i = 0; i < element_tags.size(); ++i) element_tags[i] = i + 1;
    gmsh::model::mesh::addElementsByType(1, 2, element_tags, triangle_nodes);
    // No feature angle splits a smooth interface; forReparametrization cuts
    // the closed surface into patches with one map each.
    gmsh::model::mesh::classifySurfaces(M_PI / 4, true, true, M_PI);
    gmsh::model::mesh::createGeometry();
    gmsh::model::mesh::setSizeCallback(
        [size](int, int, double x, double y, double z) { return size(Vector3d(x, y, z)); });
    gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
    gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
    gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
    gmsh::option::setNumber("Mesh.ElementOrder", 1);
    gmsh::model::mesh::generate(2);
  });
  session.run("reading the resampled interface", [&] {
    std::vector<std::size_t> tags;
    std::vector<double> coordinates, parametric;
    gmsh::model::mesh::getNodes(tags, coordinates, parametric, -1, -1, true, false);
    std::map<std::size_t, int> index;
    for (std::size_t i = 0; i < tags.size(); ++i)
      if (index.emplace(tags[i], static_cast<int>(out.vertices.size())).second)
        out.vertices.emplace_back(coordinates[3 * i], coordinates[3 * i + 1],
                                  coordinates[3 * i + 2]);
    std::vector<std::size_t> element_tags, nodes;
    gmsh::model::mesh::getElementsByType(2, element_tags, nodes, -1);
    for (std::size_t i = 0; i < nodes.size(); i += 3)
      out.triangles.push_back({index.at(nodes[i]), index.at(nodes[i + 1]), index.at(nodes[i + 2])});
  });
  if (out.triangles.empty()) throw MeshError("resampling an interface: gmsh made no triangles");
  return out;
}

}  // namespace

std::array<Vector3d, 6> InterfaceSurface::triangle_nodes(int t) const {
  const auto& tri = triangles[t];
  return {vertices[tri[0]], vertices[tri[1]], vertices[tri[2]],
          edge_nodes[t][0], edge_nodes[t][1], edge_nodes[t][2]};
}

InterfaceSurface interface_surface(const mesh::Mesh& m, int object) {
  InterfaceSurface s;
  std::map<int, int> vertex_of_node;
  for (std::size_t f = 0; f < m.interface_faces.size(); ++f) {
    if (m.interface_object[f] != object) continue;
    const auto& face = m.interface_faces[f];
    std::array<int, 3> tri{};
    std::array<Vector3d, 3> edges;
    std::array<int, 3> edge_mesh_nodes{};
    for (int k = 0; k < 3; ++k) {
      const auto [it, added] = vertex_of_node.emplace(face[k], static_cast<int>(s.vertices.size()));
      if (added) {
        s.vertices.push_back(m.nodes[face[k]]);
        s.mesh_vertex.push_back(face[k]);
      }
      tri[k] = it->second;
      edges[k] = m.nodes[face[3 + k]];
      edge_mesh_nodes[k] = face[3 + k];
    }
    s.triangles.push_back(tri);
    s.edge_nodes.push_back(edges);
    s.mesh_edge_node.push_back(edge_mesh_nodes);
  }
  return s;
}

double enclosed_volume(const InterfaceSurface& s) {
  double volume = 0.0;
  for (std::size_t t = 0; t < s.triangles.size(); ++t)
    integrate_on_triangle(s, static_cast<int>(t), volume_rule(),
                          [&](const element::SurfacePoint& p, double w) {
                            volume += w * p.area_scale * p.position.dot(p.normal) / 3.0;
                          });
  return volume;
}

double surface_area(const InterfaceSurface& s) {
  // The area scale is not a polynomial: the trackers' degree-7 rule.
  static const element::QuadratureRule rule = element::triangle_rule(7);
  double area = 0.0;
  for (std::size_t t = 0; t < s.triangles.size(); ++t)
    integrate_on_triangle(
        s, static_cast<int>(t), rule,
        [&](const element::SurfacePoint& p, double w) { area += w * p.area_scale; });
  return area;
}

InterfaceFit interface_fit(const InterfaceSurface& s,
                           const std::function<double(const Vector3d&)>& size) {
  InterfaceFit fit;
  const auto& rule = element::triangle_rule(5);
  // The corners and edge nodes, then the rule's points (whose area scales
  // also give the triangle's area).
  constexpr std::size_t kCornersAndEdges = 6;
  std::vector<Vector3d> samples{{0, 0, 0},   {1, 0, 0},     {0, 1, 0},
                                {0.5, 0, 0}, {0.5, 0.5, 0}, {0, 0.5, 0}};
  samples.insert(samples.end(), rule.points.begin(), rule.points.end());
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const auto x = s.triangle_nodes(static_cast<int>(t));
    const auto nodes = as_columns(x);
    double smallest = std::numeric_limits<double>::infinity(), largest = 0.0, area = 0.0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const double scale = element::surface_point(nodes, samples[i]).area_scale;
      smallest = std::min(smallest, scale);
      largest = std::max(largest, scale);
      if (i >= kCornersAndEdges)
        area += rule.weights[i - kCornersAndEdges] * scale;  // the rule's points
    }
    fit.curved_shape =
        std::min(fit.curved_shape, mesh::triangle_shape(x[0], x[1], x[2]) * smallest / largest);
    const double side = std::sqrt(4.0 * area / std::sqrt(3.0));
    const double target = size((x[0] + x[1] + x[2]) / 3.0);
    fit.size_mismatch = std::max({fit.size_mismatch, side / target, target / side});
  }
  return fit;
}

InterfaceSurface resample_interface(const InterfaceSurface& old,
                                    const std::function<double(const Vector3d&)>& size,
                                    ResamplingReport* report) {
  const StraightTriangulation straight = mesh_surface(old, size);
  const SurfaceProjector projector(old);
  InterfaceSurface s;
  // Every node on the curved surface, with the surface's normal there (the
  // direction of the volume-restoring offset).
  std::vector<Vector3d> vertex_normal;
  for (const Vector3d& x : straight.vertices) {
    const SurfaceHit hit = projector.closest(x);
    s.vertices.push_back(hit.position);
    vertex_normal.push_back(hit.normal);
    s.vertex_origin.push_back(hit.origin);
  }
  // Outward triangles: gmsh's patches need not agree with each other, the
  // old surface's normal decides each triangle.
  for (auto tri : straight.triangles) {
    const Vector3d& a = s.vertices[tri[0]];
    const Vector3d n = (s.vertices[tri[1]] - a).cross(s.vertices[tri[2]] - a);
    if (n.dot(vertex_normal[tri[0]] + vertex_normal[tri[1]] + vertex_normal[tri[2]]) < 0.0)
      std::swap(tri[1], tri[2]);
    s.triangles.push_back(tri);
  }
  std::map<Edge, SurfaceHit> edge_node;
  for (const auto& tri : s.triangles) {
    std::array<Vector3d, 3> edges;
    std::array<InterfaceSurface::Origin, 3> origins;
    for (int k = 0; k < 3; ++k) {
      const auto& e = mesh::kTriangleEdges[k];
      const Edge key = edge_key(tri[e[0]], tri[e[1]]);
      auto it = edge_node.find(key);
      if (it == edge_node.end())
        it = edge_node
                 .emplace(key,
                          projector.closest(0.5 * (s.vertices[key.first] + s.vertices[key.second])))
                 .first;
      edges[k] = it->second.position;
      origins[k] = it->second.origin;
    }
    s.edge_nodes.push_back(edges);
    s.edge_node_origin.push_back(origins);
  }
  if (!old.resampled()) {  // a mesh's surface: name its nodes
    const auto name_nodes = [&old](InterfaceSurface::Origin& o) {
      for (int c = 0; c < 3; ++c) o.mesh_nodes[c] = old.mesh_vertex[old.triangles[o.triangle][c]];
      for (int k = 0; k < 3; ++k) o.mesh_nodes[3 + k] = old.mesh_edge_node[o.triangle][k];
    };
    for (auto& o : s.vertex_origin) name_nodes(o);
    for (auto& origins : s.edge_node_origin)
      for (auto& o : origins) name_nodes(o);
  }
  // One offset delta along the normals restores the volume: V(delta) is
  // smooth with dV/d delta = the area (to the normals' spread), so Newton
  // with the area as slope converges in a few steps.
  const double volume = enclosed_volume(old);
  const double area = surface_area(old);
  const std::vector<Vector3d> vertices = s.vertices;
  const auto offset_by = [&](double delta) {
    for (std::size_t i = 0; i < vertices.size(); ++i)
      s.vertices[i] = vertices[i] + delta * vertex_normal[i];
    for (std::size_t t = 0; t < s.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const auto& e = mesh::kTriangleEdges[k];
        const SurfaceHit& hit = edge_node.at(edge_key(s.triangles[t][e[0]], s.triangles[t][e[1]]));
        s.edge_nodes[t][k] = hit.position + delta * hit.normal;
      }
  };
  double delta = 0.0, change = enclosed_volume(s) / volume - 1.0;
  for (int iteration = 0; iteration < 20 && std::abs(change) > 1e-15; ++iteration) {
    delta -= change * volume / area;
    offset_by(delta);
    change = enclosed_volume(s) / volume - 1.0;
  }
  if (report) {
    report->triangles_before = static_cast<int>(old.triangles.size());
    report->triangles_after = static_cast<int>(s.triangles.size());
    double largest_size = 0.0;
    for (const Vector3d& x : s.vertices) largest_size = std::max(largest_size, size(x));
    report->volume_offset = std::abs(delta) / largest_size;
    report->volume_change = std::abs(change);
  }
  return s;
}

}  // namespace softflow::geometry
