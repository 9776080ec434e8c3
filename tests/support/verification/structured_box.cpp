#include "support/verification/structured_box.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>
#include <unordered_map>

namespace softflow::mesh {

namespace {

// The 6 Kuhn tetrahedra of a unit cube: paths from corner 0 to corner 7
// adding one coordinate bit at a time (bit 0 = x, 1 = y, 2 = z).
constexpr int kKuhn[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                             {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

class EdgeNodes {
 public:
  explicit EdgeNodes(Mesh& mesh) : mesh_(mesh), n_vertices_(mesh.n_nodes()) {}
  int get(int a, int b) {
    const long key = static_cast<long>(std::min(a, b)) * n_vertices_ + std::max(a, b);
    auto [it, inserted] = map_.try_emplace(key, -1);
    if (inserted) {
      it->second = static_cast<int>(mesh_.nodes.size());
      mesh_.nodes.push_back(0.5 * (mesh_.nodes[a] + mesh_.nodes[b]));
      mesh_.is_vertex.push_back(0);
    }
    return it->second;
  }

 private:
  Mesh& mesh_;
  long n_vertices_;  // keys are built from vertex indices only
  std::unordered_map<long, int> map_;
};

}  // namespace

namespace {

// Identifies nodes on the max face of `axis` with their images on the min face.
void identify_periodic(Mesh& mesh, int axis, double length, double tol) {
  auto key = [&](const Point& x) {
    std::array<long, 3> k{};
    for (int d = 0; d < 3; ++d) k[d] = d == axis ? 0 : std::lround(x[d] / tol);
    return k;
  };
  std::map<std::array<long, 3>, int> min_face;
  for (int i = 0; i < mesh.n_nodes(); ++i)
    if (std::abs(mesh.nodes[i][axis] + length / 2) < tol) min_face[key(mesh.nodes[i])] = i;
  for (int i = 0; i < mesh.n_nodes(); ++i)
    if (std::abs(mesh.nodes[i][axis] - length / 2) < tol) mesh.periodic_master[i] = min_face.at(key(mesh.nodes[i]));
}

}  // namespace

Mesh structured_box(const Box& box, int nx, int ny, int nz) {
  Mesh mesh;
  mesh.box = box;
  const Point lo(-box.length / 2, -box.height / 2, -box.width / 2);
  const Point h(box.length / nx, box.height / ny, box.width / nz);
  auto vertex = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        mesh.nodes.emplace_back(lo.x() + i * h.x(), lo.y() + j * h.y(), lo.z() + k * h.z());
        mesh.is_vertex.push_back(1);
      }
  EdgeNodes edges(mesh);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& kuhn : kKuhn) {
          Tet10 tet{};
          for (int a = 0; a < 4; ++a) {
            const int c = kuhn[a];
            tet[a] = vertex(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
          }
          // Positive orientation: swap two vertices if the volume is negative.
          const Point e1 = mesh.nodes[tet[1]] - mesh.nodes[tet[0]];
          const Point e2 = mesh.nodes[tet[2]] - mesh.nodes[tet[0]];
          const Point e3 = mesh.nodes[tet[3]] - mesh.nodes[tet[0]];
          if (e1.cross(e2).dot(e3) < 0) std::swap(tet[2], tet[3]);
          for (int e = 0; e < 6; ++e) tet[4 + e] = edges.get(tet[kTetEdges[e][0]], tet[kTetEdges[e][1]]);
          mesh.tets.push_back(tet);
          mesh.tet_region.push_back(0);
        }

  // Boundary triangles: tet faces whose three vertices lie on one box face.
  constexpr int kFaces[4][3] = {{0, 1, 2}, {0, 1, 3}, {1, 2, 3}, {0, 2, 3}};
  const Point hi = -lo;
  const double tol = 1e-9 * std::max({box.length, box.height, box.width});
  for (const Tet10& tet : mesh.tets)
    for (const auto& f : kFaces) {
      for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
          const double plane = side == 0 ? lo[axis] : hi[axis];
          bool on = true;
          for (int v : f) on = on && std::abs(mesh.nodes[tet[v]][axis] - plane) < tol;
          if (!on) continue;
          Triangle6 tri{tet[f[0]], tet[f[1]], tet[f[2]], 0, 0, 0};
          auto edge_node = [&](int a, int b) {
            for (int e = 0; e < 6; ++e) {
              const int p = tet[kTetEdges[e][0]], q = tet[kTetEdges[e][1]];
              if ((p == a && q == b) || (p == b && q == a)) return tet[4 + e];
            }
            return -1;
          };
          for (int e = 0; e < 3; ++e)
            tri[3 + e] = edge_node(tri[kTriangleEdges[e][0]], tri[kTriangleEdges[e][1]]);
          if ((axis == 0 && box.periodic_x) || (axis == 2 && box.periodic_z)) continue;
          static constexpr BoundaryTag kTag[3][2] = {{BoundaryTag::x_min, BoundaryTag::x_max},
                                                     {BoundaryTag::wall_bottom, BoundaryTag::wall_top},
                                                     {BoundaryTag::z_min, BoundaryTag::z_max}};
          mesh.boundary_faces.push_back(tri);
          mesh.boundary_face_tag.push_back(kTag[axis][side]);
        }
    }
  if (box.periodic_x || box.periodic_z) {
    mesh.periodic_master.resize(mesh.n_nodes());
    for (int i = 0; i < mesh.n_nodes(); ++i) mesh.periodic_master[i] = i;
    const double tol = 1e-6 * std::min({h.x(), h.y(), h.z()});
    if (box.periodic_x) identify_periodic(mesh, 0, box.length, tol);
    if (box.periodic_z) identify_periodic(mesh, 2, box.width, tol);
    // Close the map: a corner node maps through x then z to its representative.
    for (int& m : mesh.periodic_master)
      while (mesh.periodic_master[m] != m) m = mesh.periodic_master[m];
  }
  return mesh;
}

void map_nodes(Mesh& mesh, const std::function<Point(const Point&)>& map) {
  for (Point& x : mesh.nodes) x = map(x);
}

}  // namespace softflow::mesh
