#include "softflow/fem/mesh_transfer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

#include <Eigen/LU>
#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/fem/tabulation.hpp"

namespace softflow::fem {

using Eigen::Vector3d;

// ---------------------------------------------------------------------------
// RegionLocator
// ---------------------------------------------------------------------------

// A bounding-box tree: each node's box holds its elements' boxes; leaves
// hold at most kLeafSize elements. Boxes are those of the 10 geometry nodes,
// padded by a tenth of their size: a curved P2 element may bulge slightly
// past the hull of its nodes.
struct RegionLocator::Tree {
  static constexpr int kLeafSize = 4;
  struct Node {
    Vector3d lo, hi;
    int first = 0, count = 0;  // leaf: elements[first, first + count)
    int left = -1, right = -1;
  };
  std::vector<int> elements;
  std::vector<Vector3d> lo, hi;  // per element, indexed as `elements`' entries
  std::vector<Node> nodes;

  int build(int first, int count) {
    Node n;
    n.lo = Vector3d::Constant(std::numeric_limits<double>::infinity());
    n.hi = -n.lo;
    for (int i = first; i < first + count; ++i) {
      n.lo = n.lo.cwiseMin(lo[elements[i]]);
      n.hi = n.hi.cwiseMax(hi[elements[i]]);
    }
    const int index = static_cast<int>(nodes.size());
    nodes.push_back(n);
    if (count <= kLeafSize) {
      nodes[index].first = first;
      nodes[index].count = count;
      return index;
    }
    int axis = 0;
    (n.hi - n.lo).maxCoeff(&axis);
    const int half = count / 2;
    std::nth_element(elements.begin() + first, elements.begin() + first + half, elements.begin() + first + count,
                     [&](int a, int b) { return lo[a][axis] + hi[a][axis] < lo[b][axis] + hi[b][axis]; });
    const int left = build(first, half);
    const int right = build(first + half, count - half);
    nodes[index].left = left;
    nodes[index].right = right;
    return index;
  }

  // Elements whose box, grown by `pad`, contains x.
  void candidates(const Vector3d& x, double pad, std::vector<int>& out) const {
    std::vector<int> stack{0};
    while (!stack.empty()) {
      const Node& n = nodes[stack.back()];
      stack.pop_back();
      if ((x.array() < n.lo.array() - pad).any() || (x.array() > n.hi.array() + pad).any()) continue;
      if (n.left < 0) {
        for (int i = n.first; i < n.first + n.count; ++i) {
          const int e = elements[i];
          if ((x.array() >= lo[e].array() - pad).all() && (x.array() <= hi[e].array() + pad).all())
            out.push_back(e);
        }
      } else {
        stack.push_back(n.left);
        stack.push_back(n.right);
      }
    }
  }
};

RegionLocator::RegionLocator(const mesh::Mesh& mesh, int region) : mesh_(mesh), tree_(std::make_unique<Tree>()) {
  Tree& t = *tree_;
  t.lo.resize(mesh.n_tets());
  t.hi.resize(mesh.n_tets());
  for (int e = 0; e < mesh.n_tets(); ++e) {
    if (mesh.tet_region[e] != region) continue;
    Vector3d lo = mesh.nodes[mesh.tets[e][0]], hi = lo;
    for (int node : mesh.tets[e]) {
      lo = lo.cwiseMin(mesh.nodes[node]);
      hi = hi.cwiseMax(mesh.nodes[node]);
    }
    const Vector3d pad = Vector3d::Constant(0.1 * (hi - lo).maxCoeff());
    t.lo[e] = lo - pad;
    t.hi[e] = hi + pad;
    t.elements.push_back(e);
  }
  if (t.elements.empty()) throw InputError(fmt::format("the mesh has no element in region {}", region));
  t.build(0, static_cast<int>(t.elements.size()));
}

RegionLocator::~RegionLocator() = default;
RegionLocator::RegionLocator(RegionLocator&&) noexcept = default;

namespace {

// Reference coordinates of x in element `tet` by Newton on the quadratic
// map (from the centroid; a few iterations for points in or near the
// element), and how far outside the reference tetrahedron they lie.
RegionLocator::Hit invert(const mesh::Mesh& m, int tet, const Vector3d& x) {
  const element::TetNodes nodes = tet_nodes(m, tet);
  RegionLocator::Hit hit;
  hit.tet = tet;
  Vector3d xi(0.25, 0.25, 0.25);
  for (int it = 0; it < 30; ++it) {
    const auto n = element::p2_tet_values(xi);
    Vector3d r = -x;
    for (int k = 0; k < 10; ++k) r += n[k] * nodes.col(k);
    const Eigen::Matrix3d j = nodes * element::p2_tet_gradients(xi);
    const Vector3d step = j.partialPivLu().solve(r);
    xi -= step;
    if (!xi.allFinite() || xi.cwiseAbs().maxCoeff() > 1e3) break;  // diverging: far outside
    if (step.norm() < 1e-15) break;
  }
  hit.xi = xi;
  hit.outside = xi.allFinite() ? std::max({0.0, -xi.minCoeff(), xi.sum() - 1.0})
                               : std::numeric_limits<double>::infinity();
  return hit;
}

}  // namespace

RegionLocator::Hit RegionLocator::locate(const Vector3d& x) const {
  // Elements whose box holds x first; a point outside every box (just
  // outside the region) looks in ever larger neighbourhoods for the element
  // it lies least outside of.
  const Tree& t = *tree_;
  const double size = (t.nodes[0].hi - t.nodes[0].lo).maxCoeff();
  std::vector<int> near;
  Hit best;
  best.outside = std::numeric_limits<double>::infinity();
  for (double pad = 0.0; pad <= 2.0 * size; pad = pad == 0.0 ? 1e-6 * size : 4.0 * pad) {
    near.clear();
    t.candidates(x, pad, near);
    std::sort(near.begin(), near.end());  // the lowest-numbered of equals: independent of the tree
    for (int e : near) {
      const Hit hit = invert(mesh_, e, x);
      if (hit.outside < best.outside) best = hit;
      if (best.outside <= 1e-12) return best;
    }
    if (std::isfinite(best.outside)) return best;
  }
  throw MeshError(fmt::format("no element of the old mesh near ({}, {}, {})", x.x(), x.y(), x.z()));
}

// ---------------------------------------------------------------------------
// MeshTransfer
// ---------------------------------------------------------------------------

MeshTransfer::MeshTransfer(const mesh::Mesh& old_mesh, const mesh::Mesh& new_mesh,
                           std::span<const int> new_node_of_old)
    : old_(old_mesh), new_(new_mesh), old_node_of_new_(new_mesh.n_nodes(), -1) {
  if (static_cast<int>(new_node_of_old.size()) != old_mesh.n_nodes())
    throw InputError("MeshTransfer: new_node_of_old must have one entry per old node");
  for (int i = 0; i < old_mesh.n_nodes(); ++i)
    if (new_node_of_old[i] >= 0) old_node_of_new_.at(new_node_of_old[i]) = i;
  int regions = 0;
  for (int r : old_mesh.tet_region) regions = std::max(regions, r + 1);
  for (int r = 0; r < regions; ++r) locators_.emplace_back(old_mesh, r);
}

MeshTransfer::~MeshTransfer() = default;

const MeshTransfer::Place& MeshTransfer::place(int node, int region) const {
  const long long key = static_cast<long long>(node) * (static_cast<long long>(locators_.size()) + 1) + region;
  const auto it = places_.find(key);
  if (it != places_.end()) return it->second;
  Place p;
  p.old_node = old_node_of_new_[node];
  if (p.old_node < 0) {
    if (region < 0 || region >= static_cast<int>(locators_.size()))
      throw InputError(fmt::format("MeshTransfer: region {} is not one of the old mesh's", region));
    p.hit = locators_[region].locate(new_.nodes[node]);
    largest_outside_ = std::max(largest_outside_, p.hit.outside);
  }
  return places_.emplace(key, p).first->second;
}

std::vector<double> MeshTransfer::transfer(const Space& old_space, const Space& new_space, int components,
                                           std::span<const double> old_values) const {
  if (old_space.degree() != new_space.degree() || old_space.continuity() != new_space.continuity())
    throw InputError(fmt::format("MeshTransfer: cannot transfer a {} field to a {} space", old_space.describe(),
                                 new_space.describe()));
  if (static_cast<int>(old_values.size()) != old_space.n_dofs() * components)
    throw InputError(fmt::format("MeshTransfer: {} old values for {} dofs x {} components", old_values.size(),
                                 old_space.n_dofs(), components));
  std::vector<double> out(static_cast<std::size_t>(new_space.n_dofs()) * components, 0.0);
  const int n_k = old_space.n_element_nodes();
  for (int dof = 0; dof < new_space.n_dofs(); ++dof) {
    const int node = new_space.node_of(dof), region = new_space.region_of(dof);
    const Place& p = place(node, region);
    double* value = out.data() + static_cast<std::size_t>(dof) * components;
    if (p.old_node >= 0) {
      // The same node in both meshes: its own copy, exactly.
      const int old_dof = old_space.dof(p.old_node, region);
      if (old_dof < 0)
        throw InputError(fmt::format("MeshTransfer: old node {} has no value for region {}", p.old_node, region));
      for (int c = 0; c < components; ++c) value[c] = old_values[static_cast<std::size_t>(old_dof) * components + c];
      continue;
    }
    // The old field's polynomial in the old element of the same region.
    if (old_space.continuity() == Continuity::on_interfaces)
      throw InputError("MeshTransfer: an interface-only field has a value off the carried interface nodes");
    const auto dofs = old_space.element_dofs(p.hit.tet);
    const auto n = weights(old_space.degree(), p.hit);
    for (int k = 0; k < n_k; ++k)
      for (int c = 0; c < components; ++c)
        value[c] += n[k] * old_values[static_cast<std::size_t>(dofs[k]) * components + c];
  }
  return out;
}

std::array<double, 10> MeshTransfer::weights(int degree, const RegionLocator::Hit& hit) {
  std::array<double, 10> n{};
  if (degree == 2) return element::p2_tet_values(hit.xi);
  const auto p1 = element::p1_tet_values(hit.xi);
  std::copy(p1.begin(), p1.end(), n.begin());
  return n;
}

std::vector<double> MeshTransfer::transfer(const DofMap& old_dofs, const DofMap& new_dofs,
                                           std::span<const double> old_values) const {
  if (old_dofs.n_fields() != new_dofs.n_fields())
    throw InputError("MeshTransfer: the dof maps compose different fields");
  for (int f = 0; f < old_dofs.n_fields(); ++f) {
    const FieldSpec &a = old_dofs.field(f), &b = new_dofs.field(f);
    if (a.name != b.name || a.components != b.components || a.space->degree() != b.space->degree() ||
        a.space->continuity() != b.space->continuity())
      throw InputError(fmt::format("MeshTransfer: field {} differs between the dof maps ('{}', '{}')", f, a.name,
                                   b.name));
  }
  if (static_cast<int>(old_values.size()) != old_dofs.n_dofs())
    throw InputError(fmt::format("MeshTransfer: {} old values for {} dofs", old_values.size(), old_dofs.n_dofs()));
  std::vector<double> out(new_dofs.n_dofs(), 0.0);
  for (int dof = 0; dof < new_dofs.n_dofs(); ++dof) {
    const int f = new_dofs.field_of(dof), c = new_dofs.component_of(dof);
    const int node = new_dofs.node_of(dof), region = new_dofs.region_of(dof);
    const Place& p = place(node, region);
    if (p.old_node >= 0) {
      const int old_dof = old_dofs.dof(f, p.old_node, region, c);
      if (old_dof < 0)
        throw InputError(fmt::format("MeshTransfer: old node {} has no '{}' value for region {}", p.old_node,
                                     old_dofs.field(f).name, region));
      out[dof] = old_values[old_dof];
      continue;
    }
    const FieldSpec& field = old_dofs.field(f);
    if (field.space->continuity() == Continuity::on_interfaces)
      throw InputError(fmt::format("MeshTransfer: '{}' has a value off the carried interface nodes", field.name));
    // Element dofs of field f: node by node, components innermost.
    const auto dofs = old_dofs.element_dofs(p.hit.tet).subspan(old_dofs.element_offset(f),
                                                                old_dofs.element_field_size(f));
    const auto n = weights(field.space->degree(), p.hit);
    const int n_k = field.space->n_element_nodes();
    for (int k = 0; k < n_k; ++k) out[dof] += n[k] * old_values[dofs[k * field.components + c]];
  }
  return out;
}

std::vector<Vector3d> MeshTransfer::transfer_nodal(std::span<const Vector3d> old_values) const {
  if (static_cast<int>(old_values.size()) != old_.n_nodes())
    throw InputError("MeshTransfer: transfer_nodal needs one value per old node");
  // The lowest region touching each new node (the field is continuous).
  std::vector<int> region(new_.n_nodes(), std::numeric_limits<int>::max());
  for (int t = 0; t < new_.n_tets(); ++t)
    for (int node : new_.tets[t]) region[node] = std::min(region[node], new_.tet_region[t]);
  std::vector<Vector3d> out(new_.n_nodes(), Vector3d::Zero());
  for (int node = 0; node < new_.n_nodes(); ++node) {
    const Place& p = place(node, region[node]);
    if (p.old_node >= 0) {
      out[node] = old_values[p.old_node];
      continue;
    }
    const auto n = element::p2_tet_values(p.hit.xi);
    for (int k = 0; k < 10; ++k) out[node] += n[k] * old_values[old_.tets[p.hit.tet][k]];
  }
  return out;
}

}  // namespace softflow::fem
