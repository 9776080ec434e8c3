// Accuracy study, suspect 1: the ellipsoid fit (analysis::fit_ellipsoid) and
// its node sampling, on exact geometry.
//
//   ellipsoid_fit_sampling [equator_nodes...]  > table.txt
//
// An ellipsoid with semi-axes (1.12, 0.89, 1.0), rotated by 40 deg about z
// (in the shear plane), is meshed by geometry::build_shear_cell. Its interface
// nodes are fitted (a) by the library's unweighted fit, (b) by a weighted fit
// with the P2 quadrature weights (int_T N_k ds: vertices ~0, edge nodes ~A/3),
// (c) by a weighted fit with the lumped weights of the 4 linear sub-triangles
// (each node 1/3 of the sub-triangles it touches). Exact: D = 0.23/2.01,
// theta = 40 deg.
//
// Part A: nodes as meshed (are they on the surface? errors in D, theta).
// Part B: the same nodes moved normally by a non-ellipsoidal perturbation
// eps * P(x) (a drop in shear is not exactly an ellipsoid); the reference is
// the continuous area-weighted fit, approximated with a degree-7 rule on the
// curved triangles of the finest mesh. This shows how much the sampling of a
// non-ellipsoidal shape moves D with N.
#include <cmath>
#include <cstdio>
#include <algorithm>
#include <array>
#include <cstdlib>
#include <vector>

#include <Eigen/Dense>

#include "softflow/analysis/ellipsoid_fit.hpp"
#include "softflow/element/isoparametric.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/physics/interface/interface_mesh.hpp"

using namespace softflow;
using Eigen::Vector3d;

namespace {

const Vector3d kAxes(1.12, 0.89, 1.0);
constexpr double kRotDeg = 40.0;

struct Fit {
  double D = 0, theta = 0;
};

// Weighted least squares for a x^2 + b y^2 + c z^2 + d xy + e xz + f yz + g x
// + h y + i z = 1 and its reduction to D and theta, following the
// conventions of analysis::EllipsoidFit (W = axis nearest z).
// Like the library, the points are centred first (the algebraic fit is not
// translation invariant for points off an ellipsoid), here at their weighted mean.
Fit weighted_fit(const std::vector<Vector3d>& p_in, const std::vector<double>& w) {
  Vector3d origin = Vector3d::Zero();
  double wsum = 0;
  for (std::size_t i = 0; i < p_in.size(); ++i)
    origin += std::max(w[i], 0.0) * p_in[i], wsum += std::max(w[i], 0.0);
  origin /= wsum;
  std::vector<Vector3d> p(p_in.size());
  for (std::size_t i = 0; i < p_in.size(); ++i) p[i] = p_in[i] - origin;
  Eigen::MatrixXd A(p.size(), 9);
  Eigen::VectorXd rhs(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double s = std::sqrt(std::max(w[i], 0.0));  // P2 vertex weights can be slightly negative
    const Vector3d& x = p[i];
    A.row(i) << x.x() * x.x(), x.y() * x.y(), x.z() * x.z(), x.x() * x.y(), x.x() * x.z(),
        x.y() * x.z(), x.x(), x.y(), x.z();
    A.row(i) *= s;
    rhs(i) = s;
  }
  const Eigen::VectorXd q = A.colPivHouseholderQr().solve(rhs);
  Eigen::Matrix3d M;
  M << q(0), q(3) / 2, q(4) / 2, q(3) / 2, q(1), q(5) / 2, q(4) / 2, q(5) / 2, q(2);
  const Vector3d g(q(6), q(7), q(8));
  const Vector3d c = -0.5 * M.inverse() * g;
  const double k = 1.0 + c.dot(M * c);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(M / k);
  Vector3d semi;
  for (int j = 0; j < 3; ++j) semi(j) = 1.0 / std::sqrt(es.eigenvalues()(j));
  int iw = 0;
  for (int j = 1; j < 3; ++j)
    if (std::abs(es.eigenvectors()(2, j)) > std::abs(es.eigenvectors()(2, iw))) iw = j;
  int a = (iw + 1) % 3, b = (iw + 2) % 3;
  if (semi(a) < semi(b)) std::swap(a, b);
  Fit f;
  f.D = (semi(a) - semi(b)) / (semi(a) + semi(b));
  const Vector3d dir = es.eigenvectors().col(a);
  double th = std::atan2(dir.y(), dir.x()) * 180.0 / M_PI;
  while (th > 90.0) th -= 180.0;
  while (th <= -90.0) th += 180.0;
  f.theta = th;
  return f;
}

Eigen::Matrix3d rotation() {
  const double t = kRotDeg * M_PI / 180.0;
  Eigen::Matrix3d R;
  R << std::cos(t), -std::sin(t), 0, std::sin(t), std::cos(t), 0, 0, 0, 1;
  return R;
}

// Non-ellipsoidal perturbation amplitude field (body frame): a mix of
// l = 3 and l = 4 shapes, O(1) on the surface.
double perturbation(const Vector3d& x) {
  const Vector3d y = rotation().transpose() * x;
  return y.x() * y.y() * y.z() * 3.0 + (y.x() * y.x() * y.x() * y.x() - y.y() * y.y() * y.y() * y.y());
}

// Exact outward normal of the ellipsoid at a (surface) point.
Vector3d ellipsoid_normal(const Vector3d& x) {
  const Eigen::Matrix3d R = rotation();
  const Vector3d y = R.transpose() * x;
  const Vector3d g(y.x() / (kAxes.x() * kAxes.x()), y.y() / (kAxes.y() * kAxes.y()),
                   y.z() / (kAxes.z() * kAxes.z()));
  return (R * g).normalized();
}

Vector3d project_to_ellipsoid(const Vector3d& x) {
  // radial scaling onto the exact surface
  const Vector3d y = rotation().transpose() * x;
  const double r = std::sqrt(std::pow(y.x() / kAxes.x(), 2) + std::pow(y.y() / kAxes.y(), 2) +
                             std::pow(y.z() / kAxes.z(), 2));
  return x / r;
}

struct Meshed {
  int n = 0, n_nodes = 0, eff_equator = 0;
  std::vector<Vector3d> x;
  std::vector<char> vertex;
  std::vector<double> w_p2, w_lumped;
  physics::InterfaceMesh s;
};

Meshed mesh_ellipsoid(int n) {
  geometry::ShearCellSpec spec;
  spec.box.length = spec.box.height = spec.box.width = 4.0;
  spec.box.periodic_x = spec.box.periodic_z = false;
  geometry::ObjectSpec o;
  o.shape = geometry::ObjectShape::ellipsoid;
  o.semi_axes = kAxes;
  o.rotation_deg = Vector3d(0, 0, kRotDeg);
  spec.objects.push_back(o);
  spec.sizing.equator_nodes = n;
  spec.sizing.far_size = 1.0;
  geometry::MeshReport rep;
  const auto mesh = geometry::build_shear_cell(spec, &rep);
  Meshed m;
  m.n = n;
  m.eff_equator = rep.n_equator_nodes;
  m.s = physics::extract_interface(mesh, 1);
  m.x = physics::interface_positions(m.s, mesh);
  m.n_nodes = m.s.n_nodes();
  m.vertex.resize(m.n_nodes);
  for (int i = 0; i < m.n_nodes; ++i) m.vertex[i] = mesh.is_vertex[m.s.volume_node[i]];
  m.w_p2.assign(m.n_nodes, 0.0);
  m.w_lumped.assign(m.n_nodes, 0.0);
  static const element::QuadratureRule rule = element::triangle_rule(7);
  // 4 linear sub-triangles of the 6-node triangle (local node indices)
  static const int sub[4][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}};
  for (const auto& tri : m.s.triangles) {
    element::TriangleNodes X;
    for (int k = 0; k < 6; ++k) X.col(k) = m.x[tri[k]];
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(X, rule.points[q]);
      const auto N = element::p2_triangle_values(rule.points[q]);
      for (int k = 0; k < 6; ++k) m.w_p2[tri[k]] += rule.weights[q] * p.area_scale * N[k];
    }
    for (const auto& st : sub) {
      const double a =
          0.5 * (X.col(st[1]) - X.col(st[0])).cross(X.col(st[2]) - X.col(st[0])).norm();
      for (int k = 0; k < 3; ++k) m.w_lumped[tri[st[k]]] += a / 3.0;
    }
  }
  return m;
}

// Dense quadrature-point cloud with area weights (for the continuous fit).
void quadrature_cloud(const Meshed& m, double eps, std::vector<Vector3d>& pts,
                      std::vector<double>& w) {
  static const element::QuadratureRule rule = element::triangle_rule(7);
  for (const auto& tri : m.s.triangles) {
    element::TriangleNodes X;
    for (int k = 0; k < 6; ++k) X.col(k) = m.x[tri[k]];
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(X, rule.points[q]);
      const Vector3d xs = project_to_ellipsoid(p.position);
      pts.push_back(xs + eps * perturbation(xs) * ellipsoid_normal(xs));
      w.push_back(rule.weights[q] * p.area_scale);
    }
  }
}

double order(double e0, double e1, int n0, int n1) {
  return std::log(std::abs(e0) / std::abs(e1)) / std::log(double(n1) / n0);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> ns;
  for (int i = 1; i < argc; ++i) ns.push_back(std::atoi(argv[i]));
  if (ns.empty()) ns = {16, 24, 32, 48, 64};
  const double D_exact = (kAxes.x() - kAxes.y()) / (kAxes.x() + kAxes.y());
  const double th_exact = kRotDeg;

  std::vector<Meshed> meshes;
  for (int n : ns) meshes.push_back(mesh_ellipsoid(n));

  std::printf("# Suspect 1: ellipsoid fit on a meshed exact ellipsoid, semi-axes (1.12, 0.89, 1.0), "
              "rotated 40 deg about z. D_exact = %.8f, theta_exact = 40\n", D_exact);
  std::printf("# Part A: nodes as meshed.\n");
  std::printf("# dist_v/dist_e: max distance of vertices / edge nodes to the exact surface\n");
  std::vector<std::array<double, 2>> p2_info;
  std::printf("%4s %5s %6s %10s %10s | %11s %11s | %11s %11s | %11s %11s | %8s %8s\n", "N", "Neq",
              "nodes", "dist_v", "dist_e", "dD_unw", "dth_unw", "dD_p2w", "dth_p2w", "dD_lump",
              "dth_lump", "wv/we", "sum_w");
  for (const auto& m : meshes) {
    double dv = 0, de = 0;
    for (int i = 0; i < m.n_nodes; ++i) {
      const double d = analysis::distance_to_ellipsoid(m.x[i], Vector3d::Zero(), rotation(),
                                                       kAxes);
      (m.vertex[i] ? dv : de) = std::max(m.vertex[i] ? dv : de, d);
    }
    const auto lib = analysis::fit_ellipsoid(m.x);
    const auto p2 = weighted_fit(m.x, m.w_p2);
    const auto lu = weighted_fit(m.x, m.w_lumped);
    double vmin = 1e300, vmax = -1e300, emean = 0;
    for (int i = 0; i < m.n_nodes; ++i)
      if (m.vertex[i]) vmin = std::min(vmin, m.w_p2[i]), vmax = std::max(vmax, m.w_p2[i]);
      else emean += m.w_p2[i];
    double wv = 0, we = 0;
    int nv = 0, ne = 0;
    double sw = 0;
    for (int i = 0; i < m.n_nodes; ++i) {
      (m.vertex[i] ? wv : we) += m.w_lumped[i];
      (m.vertex[i] ? nv : ne) += 1;
      sw += m.w_lumped[i];
    }
    std::printf("%4d %5d %6d %10.2e %10.2e | %11.3e %11.3e | %11.3e %11.3e | %11.3e %11.3e | %8.3f %8.4f\n",
                m.n, m.eff_equator, m.n_nodes, dv, de, lib.deformation - D_exact,
                lib.theta_deg - th_exact, p2.D - D_exact, p2.theta - th_exact, lu.D - D_exact,
                lu.theta - th_exact, (wv / nv) / (we / ne), sw);
    p2_info.push_back({vmin / (emean / ne), vmax / (emean / ne)});
  }
  std::printf("# P2 weights int N_k ds: vertex weight / mean edge-node weight in");
  for (std::size_t j = 0; j < meshes.size(); ++j)
    std::printf(" N=%d:[%.1e, %.1e]", meshes[j].n, p2_info[j][0], p2_info[j][1]);
  std::printf("\n# (negative vertex weights are clamped to 0: the p2w fit is then a fit of the edge nodes)\n");
  std::printf("# wv/we: mean lumped weight of a vertex over that of an edge node; sum_w: lumped area\n");

  // Part B: non-ellipsoidal perturbation.
  for (double eps : {0.005, 0.02}) {
    std::vector<Vector3d> qp;
    std::vector<double> qw;
    quadrature_cloud(meshes.back(), eps, qp, qw);
    const Fit ref = weighted_fit(qp, qw);
    std::printf("\n# Part B: nodes moved normally by eps * P(x), eps = %.3f; reference = continuous "
                "area-weighted fit (degree-7 rule, finest mesh): D_ref = %.8f (D_ref - D_ell = %.3e), "
                "theta_ref = %.5f\n", eps, ref.D, ref.D - D_exact, ref.theta);
    std::printf("%4s | %11s %6s %11s | %11s %6s %11s | %11s %6s %11s | %8s\n", "N", "dD_unw", "ord",
                "dth_unw", "dD_p2w", "ord", "dth_p2w", "dD_lump", "ord", "dth_lump", "maxdev");
    std::vector<Fit> prev;
    for (std::size_t j = 0; j < meshes.size(); ++j) {
      const auto& m = meshes[j];
      std::vector<Vector3d> xp(m.n_nodes);
      for (int i = 0; i < m.n_nodes; ++i) {
        const Vector3d xs = project_to_ellipsoid(m.x[i]);
        xp[i] = xs + eps * perturbation(xs) * ellipsoid_normal(xs);
      }
      const auto lib = analysis::fit_ellipsoid(xp);
      Fit unw{lib.deformation, lib.theta_deg};
      const Fit p2 = weighted_fit(xp, m.w_p2);
      const Fit lu = weighted_fit(xp, m.w_lumped);
      const Fit mine = weighted_fit(xp, std::vector<double>(xp.size(), 1.0));
      if (std::abs(mine.D - unw.D) > 1e-10)
        std::printf("# warning: own unweighted fit differs from the library's by %.2e\n", mine.D - unw.D);
      std::vector<Fit> cur{unw, p2, lu};
      std::printf("%4d", m.n);
      for (int k = 0; k < 3; ++k) {
        const double e = cur[k].D - ref.D;
        if (j == 0)
          std::printf(" | %11.3e %6s %11.3e", e, "-", cur[k].theta - ref.theta);
        else
          std::printf(" | %11.3e %6.2f %11.3e", e, order(prev[k].D - ref.D, e, meshes[j - 1].n, m.n),
                      cur[k].theta - ref.theta);
      }
      std::printf(" | %8.4f\n", lib.max_relative_deviation);
      prev = cur;
    }
  }
  return 0;
}
