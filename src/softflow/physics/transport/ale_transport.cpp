#include "softflow/physics/transport/ale_transport.hpp"

#include "softflow/fem/mesh_transfer.hpp"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/fem/supg.hpp"
#include "softflow/time/bdf.hpp"

namespace softflow::physics {

namespace {

using la::check;
// P1 (or P2) trial functions times a P2 velocity on curved elements: degree 4
// is exact on straight elements and accurate below discretisation error.
constexpr int kQuadratureDegree = 4;

}  // namespace

AleTransport::AleTransport(fem::Field& s, std::vector<SupgTau> tau_by_region)
    : s_(s),
      tau_by_region_(std::move(tau_by_region)),
      previous_(s.mesh(), s.name() + "_previous", s.dofs().field(0).space, s.components()),
      scalar_(s.mesh(), s.name() + "_component", s.dofs().field(0).space, 1),
      operator_(fem::element_matrix(scalar_)) {}

AleTransport::~AleTransport() = default;

void AleTransport::set_dirichlet(
    std::vector<int> nodes,
    std::function<Eigen::VectorXd(const Eigen::Vector3d&, int, double)> g) {
  constrained_scalar_dofs_.clear();
  const auto range = scalar_.ownership();
  const auto& space = scalar_.space();
  for (int node : nodes)
    for (const auto& copy : space.copies(node))
      if (range.owns(copy.dof)) constrained_scalar_dofs_.push_back(copy.dof);
  std::sort(constrained_scalar_dofs_.begin(), constrained_scalar_dofs_.end());
  constrained_scalar_dofs_.erase(
      std::unique(constrained_scalar_dofs_.begin(), constrained_scalar_dofs_.end()),
      constrained_scalar_dofs_.end());
  boundary_values_ = std::move(g);
}

double AleTransport::previous_step(double dt) const {
  // An unknown previous step (a checkpoint from before variable steps,
  // whose runs all had constant steps) is taken equal to this one.
  return last_dt_ > 0.0 ? last_dt_ : dt;
}

time::BdfCoefficients AleTransport::next_bdf(double dt) const {
  return time::bdf(time::bdf_order(steps_), dt, previous_step(dt));
}

time::Extrapolation AleTransport::next_extrapolation(double dt) const {
  return time::extrapolation(time::bdf_order(steps_), dt, previous_step(dt));
}

void AleTransport::step(const fem::Field& u, const fem::Field* mesh_velocity, const Source& source,
                        double dt, double t_new) {
  const auto c = next_bdf(dt);
  extrapolation_ = next_extrapolation(dt);
  const int n_c = s_.components();
  const int n_k = s_.space().n_element_nodes();
  const bool p2 = s_.space().degree() == 2;
  const auto& mesh = s_.mesh();
  const fem::TetTabulation tab(kQuadratureDegree);
  const auto range = scalar_.ownership();
  const int n_scalar = scalar_.dofs().n_dofs();

  std::vector<la::Vector> rhs(n_c);
  for (auto& b : rhs) {
    b = la::make_vector(range.size(), n_scalar);
    check(VecSet(b.get(), 0.0), "VecSet");
  }

  // (v + tau w.grad v, (a0 s_{n+1} + a1 s_n + a2 s_{n-1}) / dt + w.grad s_{n+1} - r) = 0
  Eigen::MatrixXd ke(n_k, n_k), fe(n_k, n_c), grad(n_k, 3);
  Eigen::VectorXd phi(n_k), test(n_k), w_grad(n_k);
  std::size_t e = 0;
  for (int t : scalar_.owned_elements()) {
    const auto points = fem::quadrature_points(mesh, tab, t);
    std::vector<Eigen::Vector3d> w(points.size());
    double volume = 0.0, speed = 0.0;
    for (std::size_t q = 0; q < points.size(); ++q) {
      w[q] = u.value(points[q]);
      if (mesh_velocity) w[q] -= mesh_velocity->value(points[q]);
      volume += points[q].weight;
      speed += points[q].weight * w[q].norm();
    }
    const double steady_tau = fem::supg_tau(fem::element_length(volume), speed / volume, 0.0);
    const int region = mesh.tet_region[t];
    const bool transient = region < static_cast<int>(tau_by_region_.size()) &&
                           tau_by_region_[region] == SupgTau::transient;
    const double tau = transient ? fem::transient_supg_tau(steady_tau, dt) : steady_tau;
    ke.setZero();
    fe.setZero();
    for (std::size_t q = 0; q < points.size(); ++q) {
      const auto& p = points[q];
      if (p2) {
        for (int k = 0; k < 10; ++k) phi(k) = tab.p2[p.q][k];
        grad = tab.p2_grad[p.q] * p.map.inverse_jacobian;
      } else {
        for (int k = 0; k < 4; ++k) phi(k) = tab.p1[p.q][k];
        grad = element::p1_tet_gradients() * p.map.inverse_jacobian;
      }
      w_grad = grad * w[q];
      test = phi + tau * w_grad;  // Petrov-Galerkin test functions
      ke.noalias() += p.weight * test * (c.a0 / dt * phi + w_grad).transpose();
      fem::PointValue known = -(c.a1 * s_.value(p)) / dt;
      if (c.a2 != 0.0) known -= c.a2 * previous_.value(p) / dt;
      if (source) known += source(p);
      fe.noalias() += p.weight * test * known.transpose();
    }
    operator_.matrix->set_block(operator_.blocks[e++], ke);
    const auto d = scalar_.dofs().element_dofs(t);
    for (int comp = 0; comp < n_c; ++comp) {
      const Eigen::VectorXd column = fe.col(comp);
      check(VecSetValues(rhs[comp].get(), n_k, d.data(), column.data(), ADD_VALUES),
            "VecSetValues");
    }
  }
  operator_.matrix->assemble();
  for (auto& b : rhs) {
    check(VecAssemblyBegin(b.get()), "VecAssemblyBegin");
    check(VecAssemblyEnd(b.get()), "VecAssemblyEnd");
  }

  // Constrained rows become identity rows; their right-hand sides the values.
  std::vector<PetscInt> rows(constrained_scalar_dofs_.begin(), constrained_scalar_dofs_.end());
  check(MatZeroRows(operator_.matrix->get(), static_cast<PetscInt>(rows.size()), rows.data(), 1.0,
                    nullptr, nullptr),
        "MatZeroRows");
  // Every rank assembles (collective), also one that owns no constrained row.
  std::vector<std::vector<PetscScalar>> values(n_c, std::vector<PetscScalar>(rows.size()));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const int d = static_cast<int>(rows[i]);
    const Eigen::VectorXd g = boundary_values_(mesh.nodes[scalar_.dofs().node_of(d)],
                                               scalar_.dofs().region_of(d), t_new);
    for (int comp = 0; comp < n_c; ++comp) values[comp][i] = g(comp);
  }
  for (int comp = 0; comp < n_c; ++comp) {
    check(VecSetValues(rhs[comp].get(), static_cast<PetscInt>(rows.size()), rows.data(),
                       values[comp].data(), INSERT_VALUES),
          "VecSetValues");
    check(VecAssemblyBegin(rhs[comp].get()), "VecAssemblyBegin");
    check(VecAssemblyEnd(rhs[comp].get()), "VecAssemblyEnd");
  }

  // One factorisation, one solve per component.
  const la::Solver ksp = la::lu_solver(operator_.matrix->get(), "transport_");

  check(VecCopy(s_.vector(), previous_.vector()), "VecCopy");  // s_n becomes the history
  fem::solve_by_component(ksp.get(), rhs, scalar_, s_, "transport of '" + s_.name() + "'");
  s_.update_ghosts();
  previous_.update_ghosts();
  ++steps_;
  last_dt_ = dt;
}

void AleTransport::carry_over(const AleTransport& old, const fem::MeshTransfer& transfer) {
  previous_.scatter(
      transfer.transfer(old.previous_.space(), previous_.space(), previous_.components(), old.previous_.gather()));
  steps_ = old.steps_;
  last_dt_ = old.last_dt_;
}

StatePart AleTransport::state_part() {
  return {"transport/" + s_.name(),
          [this](StateRecord& r, const std::string& p) {
            r.set(p + "steps", steps_);
            r.set(p + "last_step", last_dt_);
            previous_.save(r, p + "previous");
          },
          [this](const StateRecord& r, const std::string& p) {
            previous_.restore(r, p + "previous");
            steps_ = r.get_int(p + "steps");
            // Checkpoints from before variable steps: unknown (0), taken as
            // the next step's size (step()).
            last_dt_ = r.contains(p + "last_step") ? r.get_double(p + "last_step") : 0.0;
          }};
}

}  // namespace softflow::physics
