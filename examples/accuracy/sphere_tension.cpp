// Accuracy study, suspect 2: the surface-tension load (physics::add_surface_tension),
// the meshed sphere's volume and area, and the nodal normals (physics::node_normals),
// on a meshed unit sphere where every answer is known.
//
//   sphere_tension [equator_nodes...]  > table.txt
//
// Table 1 (geometry): max | |x| - 1 | over interface nodes, volume and area
// errors of the curved P2 surface (surface_integrals, degree-7 rule), max
// angle between node_normals and x/|x| at vertices and at edge nodes.
// Table 2 (tension): the assembled load F_k = -int grad_s N_k ds (Gamma = 1)
// tested against
//   v = x/|x| (the exact normal at the nodes):  -sum F_k.v_k -> int div_s n = 8 pi,
//   v = w(x) = (x y, y z^2, x^3 + z) a generic smooth field: -> int_S div_s w,
// and the nodal load against the exact consistent load
//   G_k = -int_{S_h} N_k (2 / R) n_exact ds :  max_k |F_k - G_k| / max_k |G_k|.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <Eigen/Dense>

#include "softflow/element/isoparametric.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/physics/interface/interface_mesh.hpp"
#include "softflow/physics/stokes/stokes_kernels.hpp"

using namespace softflow;
using Eigen::Vector3d;

namespace {

Vector3d w_field(const Vector3d& x) {
  return {x.x() * x.y(), x.y() * x.z() * x.z(), x.x() * x.x() * x.x() + x.z()};
}
Eigen::Matrix3d w_grad(const Vector3d& x) {  // G_ij = d w_i / d x_j
  Eigen::Matrix3d G;
  G << x.y(), x.x(), 0, 0, x.z() * x.z(), 2 * x.y() * x.z(), 3 * x.x() * x.x(), 0, 1;
  return G;
}

// int over the unit sphere of div_s w = tr(G) - n.G n, by a product
// Gauss-Legendre (in cos theta) x trapezoid (in phi) rule.
double exact_div_s_w() {
  const int nt = 40, np = 80;
  std::vector<double> t, wt;
  element::gauss_legendre_01(nt, t, wt);
  double sum = 0;
  for (int i = 0; i < nt; ++i) {
    const double c = 2 * t[i] - 1, s = std::sqrt(1 - c * c);
    for (int j = 0; j < np; ++j) {
      const double ph = 2 * M_PI * j / np;
      const Vector3d n(s * std::cos(ph), s * std::sin(ph), c);
      const Eigen::Matrix3d G = w_grad(n);
      sum += 2 * wt[i] * (2 * M_PI / np) * (G.trace() - n.dot(G * n));
    }
  }
  return sum;
}

double order(double e0, double e1, int n0, int n1) {
  return std::log(std::abs(e0) / std::abs(e1)) / std::log(double(n1) / n0);
}

struct Row {
  int n = 0, nodes = 0;
  double radius_dev = 0, vol_err = 0, area_err = 0, nrm_v = 0, nrm_e = 0;
  double nrm_v_rms = 0, nrm_e_rms = 0, worst_z = 0, mid_offset = 0, mid_offset_rms = 0, load_rms = 0;
  double tn_err = 0, tw_err = 0, twa = 0, load_err = 0, load_err_e = 0, load_err_v = 0;
};

Row measure(int n, double exact_w) {
  geometry::ShearCellSpec spec;
  spec.box.length = spec.box.height = spec.box.width = 4.0;
  spec.box.periodic_x = spec.box.periodic_z = false;
  spec.objects.push_back(geometry::ObjectSpec{});
  spec.sizing.equator_nodes = n;
  spec.sizing.far_size = 1.0;
  const auto mesh = geometry::build_shear_cell(spec);
  const auto s = physics::extract_interface(mesh, 1);
  const auto x = physics::interface_positions(s, mesh);
  Row r;
  r.n = n;
  r.nodes = s.n_nodes();
  for (const auto& p : x) r.radius_dev = std::max(r.radius_dev, std::abs(p.norm() - 1.0));
  const auto si = physics::surface_integrals(s, x);
  r.vol_err = si.volume - 4 * M_PI / 3;
  r.area_err = si.area - 4 * M_PI;
  const auto nn = physics::node_normals(s, x);
  int nv = 0, ne = 0;
  for (int i = 0; i < s.n_nodes(); ++i) {
    const double ang = std::acos(std::min(1.0, nn[i].dot(x[i].normalized())));
    const bool vtx = mesh.is_vertex[s.volume_node[i]];
    double& m = vtx ? r.nrm_v : r.nrm_e;
    if (vtx && ang > m) r.worst_z = x[i].z();
    m = std::max(m, ang);
    (vtx ? r.nrm_v_rms : r.nrm_e_rms) += ang * ang;
    (vtx ? nv : ne) += 1;
  }
  r.nrm_v_rms = std::sqrt(r.nrm_v_rms / nv);
  r.nrm_e_rms = std::sqrt(r.nrm_e_rms / ne);
  // Placement of the edge nodes along their edge: distance of the edge node
  // from the great-circle midpoint of its two vertices, over the edge length.
  int n_edges = 0;
  for (const auto& tri : s.triangles)
    for (int e = 0; e < 3; ++e) {
      const Vector3d& a = x[tri[mesh::kTriangleEdges[e][0]]];
      const Vector3d& b = x[tri[mesh::kTriangleEdges[e][1]]];
      const double off = (x[tri[3 + e]] - (a + b).normalized()).norm() / (b - a).norm();
      r.mid_offset = std::max(r.mid_offset, off);
      r.mid_offset_rms += off * off;
      ++n_edges;
    }
  r.mid_offset_rms = std::sqrt(r.mid_offset_rms / n_edges);
  // Assemble F and the consistent exact load G.
  std::vector<Vector3d> F(s.n_nodes(), Vector3d::Zero()), G(s.n_nodes(), Vector3d::Zero());
  static const element::QuadratureRule rule = element::triangle_rule(7);
  for (const auto& tri : s.triangles) {
    element::TriangleNodes X;
    for (int k = 0; k < 6; ++k) X.col(k) = x[tri[k]];
    physics::TriangleVelocityVector f = physics::TriangleVelocityVector::Zero();
    physics::add_surface_tension(X, 1.0, f);
    for (int k = 0; k < 6; ++k) F[tri[k]] += f.segment<3>(3 * k);
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(X, rule.points[q]);
      const auto N = element::p2_triangle_values(rule.points[q]);
      for (int k = 0; k < 6; ++k)
        G[tri[k]] -= rule.weights[q] * p.area_scale * N[k] * 2.0 * p.position.normalized();
    }
  }
  double tn = 0, tw = 0, gmax = 0, emax = 0, emax_v = 0, emax_e = 0;
  for (int i = 0; i < s.n_nodes(); ++i) {
    tn -= F[i].dot(x[i].normalized());
    tw -= F[i].dot(w_field(x[i]));
    gmax = std::max(gmax, G[i].norm());
  }
  for (int i = 0; i < s.n_nodes(); ++i) {
    const double e = (F[i] - G[i]).norm();
    emax = std::max(emax, e);
    r.load_rms += e * e;
    double& m = mesh.is_vertex[s.volume_node[i]] ? emax_v : emax_e;
    m = std::max(m, e);
  }
  r.tn_err = tn - 8 * M_PI;
  r.tw_err = tw - exact_w;
  r.twa = tn - 2 * si.area;  // consistency with the discrete area
  r.load_err = emax / gmax;
  r.load_rms = std::sqrt(r.load_rms / s.n_nodes()) / gmax;
  r.load_err_v = emax_v / gmax;
  r.load_err_e = emax_e / gmax;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> ns;
  for (int i = 1; i < argc; ++i) ns.push_back(std::atoi(argv[i]));
  if (ns.empty()) ns = {16, 24, 32, 48, 64};
  const double exact_w = exact_div_s_w();
  std::vector<Row> rows;
  for (int n : ns) rows.push_back(measure(n, exact_w));

  auto ord = [&](std::size_t j, double Row::*f) {
    return j == 0 ? NAN : order(rows[j - 1].*f, rows[j].*f, rows[j - 1].n, rows[j].n);
  };
  std::printf("# Suspect 2a: geometry of the meshed unit sphere (orders between successive N)\n");
  std::printf("%4s %6s %9s | %10s %6s | %10s %6s | %9s %6s | %9s %6s\n", "N", "nodes", "max||x|-1|",
              "vol_err", "ord", "area_err", "ord", "nrm_vtx", "ord", "nrm_edge", "ord");
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const auto& r = rows[j];
    std::printf("%4d %6d %9.1e | %10.3e %6.2f | %10.3e %6.2f | %9.3e %6.2f | %9.3e %6.2f\n", r.n,
                r.nodes, r.radius_dev, r.vol_err, ord(j, &Row::vol_err), r.area_err,
                ord(j, &Row::area_err), r.nrm_v, ord(j, &Row::nrm_v), r.nrm_e, ord(j, &Row::nrm_e));
  }
  std::printf("# nrm_vtx / nrm_edge: max angle (rad) between node_normals and x/|x|\n");
  std::printf("%4s | %9s %6s | %9s %6s | %8s | %9s %9s\n", "N", "rms_vtx", "ord", "rms_edge", "ord",
              "z_worst", "mid_off", "mid_rms");
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const auto& r = rows[j];
    std::printf("%4d | %9.3e %6.2f | %9.3e %6.2f | %8.4f | %9.3e %9.3e\n", r.n, r.nrm_v_rms,
                ord(j, &Row::nrm_v_rms), r.nrm_e_rms, ord(j, &Row::nrm_e_rms), r.worst_z,
                r.mid_offset, r.mid_offset_rms);
  }
  std::printf("# rms_*: RMS normal angle; z_worst: z of the vertex with the largest normal error (poles of\n"
              "# the OCC sphere at z = +-1); mid_off/mid_rms: max/RMS distance of an edge node from the\n"
              "# great-circle midpoint of its edge, over the edge length\n\n");
  std::printf("# Suspect 2b: tension load F_k = -int grad_s N_k (Gamma = 1); exact int div_s w = %.10f\n",
              exact_w);
  std::printf("%4s | %10s %6s | %10s | %10s %6s | %10s %6s | %10s %10s | %10s %6s\n", "N", "<F,n>-8pi", "ord",
              "<F,n>-2A_h", "<F,w>-ex", "ord", "load_err", "ord", "ld_err_vtx", "ld_err_edg", "load_rms", "ord");
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const auto& r = rows[j];
    std::printf("%4d | %10.3e %6.2f | %10.3e | %10.3e %6.2f | %10.3e %6.2f | %10.3e %10.3e | %10.3e %6.2f\n", r.n,
                r.tn_err, ord(j, &Row::tn_err), r.twa, r.tw_err, ord(j, &Row::tw_err), r.load_err,
                ord(j, &Row::load_err), r.load_err_v, r.load_err_e, r.load_rms, ord(j, &Row::load_rms));
  }
  std::printf("# load_err: max_k |F_k - G_k| / max_k |G_k|, G_k = -2 int_{S_h} N_k x/|x| ds\n");
  return 0;
}
