#include "softflow/physics/interface/interface_tracker.hpp"

#include <cmath>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/element/isoparametric.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/time/bdf.hpp"

namespace softflow::physics {

namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

const element::QuadratureRule& surface_rule() {
  static const element::QuadratureRule rule = element::triangle_rule(5);
  return rule;
}

element::TriangleNodes triangle_at(const std::array<int, 6>& tri, const std::vector<Vec3>& x) {
  element::TriangleNodes nodes;
  for (int k = 0; k < 6; ++k) nodes.col(k) = x[tri[k]];
  return nodes;
}

// dX/dt of the centre of volume X = Q / V (eqs. 2.53-2.54) while the surface
// x moves with the normal velocity u.n (u given at the nodes, P2 on each
// triangle): by Reynolds' transport theorem dQ/dt = int_S x (u.n) ds and
// dV/dt = int_S u.n ds, so dX/dt = int_S (x - X) (u.n) ds / V. Exact for a
// translation (u = V: dX/dt = V) whatever the shape.
Vec3 flow_centre_velocity(const InterfaceMesh& s, const std::vector<Vec3>& x, const std::vector<Vec3>& u) {
  static const element::QuadratureRule rule = element::triangle_rule(7);
  double volume = 0.0, volume_rate = 0.0;
  Vec3 first_moment = Vec3::Zero(), moment_rate = Vec3::Zero();
  for (const auto& tri : s.triangles) {
    const auto nodes = triangle_at(tri, x);
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(nodes, rule.points[q]);
      const double w = rule.weights[q] * p.area_scale;
      const auto phi = element::p2_triangle_values(rule.points[q]);
      Vec3 u_q = Vec3::Zero();
      for (int k = 0; k < 6; ++k) u_q += phi[k] * u[tri[k]];
      const double u_n = u_q.dot(p.normal);
      volume += w * p.normal.dot(p.position) / 3.0;
      first_moment += w * p.normal * p.position.squaredNorm() / 2.0;
      volume_rate += w * u_n;
      moment_rate += w * u_n * p.position;
    }
  }
  return (moment_rate - volume_rate * first_moment / volume) / volume;
}

}  // namespace

InterfaceTracker::InterfaceTracker(InterfaceMesh surface, std::vector<Vec3> initial_positions,
                                   const InterfaceTrackerSettings& settings)
    : surface_(std::move(surface)),
      settings_(settings),
      x_(std::move(initial_positions)),
      x_previous_(x_) {
  initial_areas_ = triangle_areas(surface_, x_);
  for (double a : initial_areas_) initial_area_ += a;
  centre_ = centre_previous_ = surface_integrals(surface_, x_).centre_of_volume();
}

std::vector<Vec3> InterfaceTracker::predict(double dt) const {
  // x_n at the first step (eq. 2.47): there is no x_{n-1} to extrapolate from.
  const int order = time::bdf_order(steps_);
  if (order == 1) return x_;
  const auto e = time::extrapolation(order, dt, last_dt_);
  std::vector<Vec3> x_hat(x_.size());
  for (std::size_t i = 0; i < x_.size(); ++i)
    x_hat[i] = e.current * x_[i] + e.previous * x_previous_[i];  // eq. 2.49
  return x_hat;
}

Vec3 InterfaceTracker::centre_velocity(const std::vector<Vec3>& predicted, double dt) {
  const Vec3 x_next = surface_integrals(surface_, predicted).centre_of_volume();
  // Its own step count: the centre is recorded at the prediction, the
  // positions at the correction.
  // The history is the corrected surfaces' centres X_n, X_{n-1}, not the
  // earlier predictions: the first prediction does not move (x_hat_1 = x_0),
  // so a history of predicted centres makes the second step's BDF2 see
  // X_0, X_0, 2 X_1 - X_0 and report three times the true velocity, which
  // slides the interface nodes of a translating object sideways.
  const auto c = time::bdf(time::bdf_order(steps_), dt, last_dt_);
  const Vec3 x_n = surface_integrals(surface_, x_).centre_of_volume();
  Vec3 u = (c.a0 * x_next + c.a1 * x_n) / dt;  // eqs. 2.51-2.52
  if (c.a2 != 0.0) u += c.a2 * surface_integrals(surface_, x_previous_).centre_of_volume() / dt;
  centre_previous_ = centre_;
  centre_ = x_next;
  ++centre_steps_;
  return u;
}

void InterfaceTracker::set_reference_areas(std::vector<double> areas) {
  if (areas.size() != surface_.triangles.size())
    throw InputError("the interface's reference areas do not fit its triangles");
  initial_area_ = 0.0;
  for (double a : areas) {
    if (!(a > 0.0)) throw InputError("an interface reference area is not positive");
    initial_area_ += a;
  }
  initial_areas_ = std::move(areas);
}

std::vector<double> InterfaceTracker::redistribution_potential(const std::vector<Vec3>& x) const {
  // -lap_s c = 1 - 1/g (eq. 2.31) in weak form: (grad_s w, grad_s c) = (w, 1 - 1/g).
  // g_e = (A_e / A_e0) / (A / A0) so that int_S 1/g ds = A (eq. 2.32); the
  // right side then integrates to zero and the pure-Neumann problem is
  // solvable; its constant is fixed by pinning one node, then removed.
  const int n = surface_.n_nodes();
  const auto areas = triangle_areas(surface_, x);
  double area = 0.0;
  for (double a : areas) area += a;
  const auto& rule = surface_rule();
  Triplets k;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  for (std::size_t e = 0; e < surface_.triangles.size(); ++e) {
    const auto& tri = surface_.triangles[e];
    const double g = (areas[e] / initial_areas_[e]) / (area / initial_area_);
    const auto nodes = triangle_at(tri, x);
    Eigen::Matrix<double, 6, 6> ke = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> be = Eigen::Matrix<double, 6, 1>::Zero();
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(nodes, rule.points[q]);
      const double w = rule.weights[q] * p.area_scale;
      ke += w * p.surface_gradients * p.surface_gradients.transpose();
      const auto phi = element::p2_triangle_values(rule.points[q]);
      for (int i = 0; i < 6; ++i) be(i) += w * phi[i] * (1.0 - 1.0 / g);
    }
    for (int i = 0; i < 6; ++i) {
      b(tri[i]) += be(i);
      for (int j = 0; j < 6; ++j) k.emplace_back(tri[i], tri[j], ke(i, j));
    }
  }
  // Pin node 0: replace its row and column by the identity.
  Triplets pinned;
  pinned.reserve(k.size());
  for (const auto& t : k)
    if (t.row() != 0 && t.col() != 0) pinned.push_back(t);
  pinned.emplace_back(0, 0, 1.0);
  b(0) = 0.0;
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.setFromTriplets(pinned.begin(), pinned.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(matrix);
  if (solver.info() != Eigen::Success)
    throw SolverError("interface redistribution: the surface Laplacian could not be factored");
  Eigen::VectorXd c = solver.solve(b);
  c.array() -= c.mean();
  return {c.data(), c.data() + n};
}

void InterfaceTracker::correct(const std::vector<Vec3>& predicted,
                               const std::vector<Vec3>& fluid_velocity, const Vec3& predicted_centre_velocity,
                               double dt) {
  // A BDF1 step (the first, or the first after restart_history) predicts
  // x_hat = x_n (eq. 2.47), so the U of eqs. 2.51-2.52 from the predicted
  // surface is (X(x_n) - X_n) / dt = 0 there, and eq. 2.48 moves the nodes
  // with (u.n) n + u_t: a translating object loses the tangential part of its
  // translation. Measured (drop at y = 1 in shear, u ~ 1, 16 equator nodes):
  // the first step changed the volume by -0.08 %, -0.28 %, -0.92 % at
  // dt = 0.025, 0.05, 0.1 (second order in u dt) and moved the centre by 92 %,
  // 86 %, 74 % of u dt; BDF2's next step then overshot (+1.1 % at dt = 0.1).
  // The flow gives U at that step instead.
  const Vec3 u_centre = steps_ == 0 ? flow_centre_velocity(surface_, predicted, fluid_velocity)
                                    : predicted_centre_velocity;
  // (w + tau a.grad_s w, (a0 x_{n+1} + a1 x_n + a2 x_{n-1})/dt + a.grad_s x_{n+1} - u - u_t) = 0
  // with a = u - U, grad_s on the predicted surface (eq. 2.48 / 2.50). The
  // operator is the same for the three components of x.
  const int n = surface_.n_nodes();
  const auto c = time::bdf(time::bdf_order(steps_), dt, last_dt_);
  const bool redistribute = settings_.redistribution_factor != 0.0;
  const std::vector<double> potential =
      redistribute ? redistribution_potential(predicted) : std::vector<double>(n, 0.0);
  const auto& rule = surface_rule();
  Triplets triplets;
  triplets.reserve(surface_.triangles.size() * 36);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
  for (const auto& tri : surface_.triangles) {
    const auto nodes = triangle_at(tri, predicted);
    double element_area = 0.0;
    std::vector<element::SurfacePoint> points;
    points.reserve(rule.size());
    for (int q = 0; q < rule.size(); ++q) {
      points.push_back(element::surface_point(nodes, rule.points[q]));
      element_area += rule.weights[q] * points.back().area_scale;
    }
    const double h = std::sqrt(element_area);
    Eigen::Matrix<double, 6, 6> ke = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 3> fe = Eigen::Matrix<double, 6, 3>::Zero();
    for (int q = 0; q < rule.size(); ++q) {
      const auto& p = points[q];
      const double w = rule.weights[q] * p.area_scale;
      const auto phi = element::p2_triangle_values(rule.points[q]);
      Vec3 u = Vec3::Zero(), history = Vec3::Zero(), u_t = Vec3::Zero();
      for (int k = 0; k < 6; ++k) {
        u += phi[k] * fluid_velocity[tri[k]];
        history += phi[k] * (c.a1 * x_[tri[k]] + c.a2 * x_previous_[tri[k]]);
        if (redistribute)
          u_t += settings_.redistribution_factor * potential[tri[k]] * p.surface_gradients.row(k).transpose();
      }
      const Vec3 a = u - u_centre;
      const Vec3 a_t = a - a.dot(p.normal) * p.normal;  // only the tangential part convects
      const double speed = a_t.norm();
      const double tau = speed > 1e-12 ? settings_.supg_beta * h / (2.0 * speed) : 0.0;
      const Eigen::Matrix<double, 6, 1> a_grad = p.surface_gradients * a;  // a.grad_s phi_k
      Eigen::Matrix<double, 6, 1> test;
      for (int i = 0; i < 6; ++i) test(i) = phi[i] + tau * a_grad(i);
      for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j) ke(i, j) += w * test(i) * (c.a0 / dt * phi[j] + a_grad(j));
        fe.row(i) += w * test(i) * (u + u_t - history / dt).transpose();
      }
    }
    for (int i = 0; i < 6; ++i) {
      rhs.row(tri[i]) += fe.row(i);
      for (int j = 0; j < 6; ++j) triplets.emplace_back(tri[i], tri[j], ke(i, j));
    }
  }
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
  solver.compute(matrix);
  if (solver.info() != Eigen::Success)
    throw SolverError("interface tracking: the SUPG surface convection system is singular");
  const Eigen::MatrixXd x_next = solver.solve(rhs);
  x_previous_ = x_;
  for (int i = 0; i < n; ++i) x_[i] = x_next.row(i).transpose();
  ++steps_;
  last_dt_ = dt;
}

void InterfaceTracker::restore(History history) {
  if (history.x.size() != x_.size() || history.x_previous.size() != x_.size())
    throw Error(fmt::format("interface history of {} nodes for a surface of {}", history.x.size(),
                            x_.size()));
  x_ = std::move(history.x);
  x_previous_ = std::move(history.x_previous);
  centre_ = history.centre;
  centre_previous_ = history.centre_previous;
  steps_ = history.steps;
  centre_steps_ = history.centre_steps;
  last_dt_ = history.last_step;
}

}  // namespace softflow::physics
