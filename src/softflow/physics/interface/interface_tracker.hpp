// Interface tracking: normal motion plus tangential redistribution (thesis §2.2.3, §2.3.2).
#pragma once

#include <vector>

#include "softflow/physics/interface/interface_mesh.hpp"

namespace softflow::physics {

struct InterfaceTrackerSettings {
  /// k of eq. 2.30, u_t = k grad_s c (thesis: 10 gamma_dot; 0 = normal motion only).
  double redistribution_factor = 10.0;
  /// beta of the SUPG parameter tau = beta h / (2 U_t); 0.5 for P2 (thesis §2.3.2).
  double supg_beta = 0.5;
};

/// Moves the interface nodes with
///   x' = ((u - U).n) n + U + u_t                          (eq. 2.29)
/// written as the surface convection equation
///   x' + (u - U).grad_s x = u + u_t                       (eq. 2.46)
/// so that the tank-treading tangential velocity never moves the nodes.
/// Discretised with SUPG on the curved P2 surface, Gear BDF1 for the first
/// step and BDF2 after (eqs. 2.47-2.50); grad_s is taken on the predicted
/// surface. u_t = k grad_s c with -lap_s c = 1 - 1/g (eq. 2.31), g the
/// element area relative to its initial area, scaled so that
/// int_S 1/g ds = area of S (eq. 2.32): the redistribution keeps the initial
/// element size distribution (the thesis's f = 1 for a uniform start).
///
/// Use per time step: x_hat = predict(dt); [move the mesh, solve Stokes with
/// the interface at x_hat]; U = centre_velocity(x_hat, dt); correct(x_hat,
/// u_at_nodes, U, dt). The step dt may change from step to step: the BDF2
/// coefficients and the predictor then take the variable-step form
/// (time::bdf) with the previous step's size, which the tracker records.
class InterfaceTracker {
 public:
  InterfaceTracker(InterfaceMesh surface, std::vector<Vec3> initial_positions,
                   const InterfaceTrackerSettings& settings);

  /// Step 1: x_hat_{n+1} = x_n (first step, eq. 2.47) or the line through
  /// x_{n-1}, x_n at t_n + dt: 2 x_n - x_{n-1} at a constant step (eq. 2.49).
  [[nodiscard]] std::vector<Vec3> predict(double dt) const;

  /// Velocity U of the centre of volume X at t_{n+1}, X from the predicted
  /// surface (eqs. 2.51-2.54). Records X_{n+1}; call once per step.
  Vec3 centre_velocity(const std::vector<Vec3>& predicted, double dt);

  /// Step 5: the corrected positions x_{n+1} (eq. 2.48 or 2.50), given the
  /// fluid velocity at the interface nodes at t_{n+1} and U.
  void correct(const std::vector<Vec3>& predicted, const std::vector<Vec3>& fluid_velocity,
               const Vec3& centre_velocity, double dt);

  [[nodiscard]] const InterfaceMesh& surface() const { return surface_; }
  [[nodiscard]] const std::vector<Vec3>& positions() const { return x_; }
  [[nodiscard]] const std::vector<Vec3>& previous_positions() const { return x_previous_; }
  [[nodiscard]] int steps() const { return steps_; }
  /// The size of the last corrected step (0 before the first).
  [[nodiscard]] double last_step() const { return last_dt_; }
  /// X of the latest recorded centre (from the predicted surface; initially x_0's).
  [[nodiscard]] const Vec3& centre() const { return centre_; }

  /// What the next steps depend on besides the surface and the settings:
  /// saved in checkpoints, so that a restarted run continues with BDF2 from
  /// exactly the same x_n, x_{n-1}, X_n, X_{n-1} and t_n - t_{n-1}.
  struct History {
    std::vector<Vec3> x, x_previous;
    Vec3 centre = Vec3::Zero(), centre_previous = Vec3::Zero();
    int steps = 0, centre_steps = 0;
    double last_step = 0.0;
  };
  [[nodiscard]] History history() const {
    return {x_, x_previous_, centre_, centre_previous_, steps_, centre_steps_, last_dt_};
  }
  /// Continues from a saved history of the same surface (the node count must match).
  void restore(History history);
  /// The next step is BDF1 with the predictor x_n, as the first: after a
  /// jump in the flow (walls that stop), where BDF2's three-level stencil
  /// would span the jump and leave an O(dt) error.
  void restart_history() {
    steps_ = 0;
    centre_steps_ = 0;
  }

  /// The triangle areas the redistribution keeps the interface's elements
  /// in proportion to (g of eq. 2.31 relative to them): those of the initial
  /// positions, unless set.
  [[nodiscard]] const std::vector<double>& reference_areas() const { return initial_areas_; }
  /// Sets them, triangle by triangle (one per surface triangle, > 0): a
  /// remesh or a restart after one carries the run's initial ones over.
  void set_reference_areas(std::vector<double> areas);

  /// The redistribution potential c on the surface x (eq. 2.31), mean zero.
  [[nodiscard]] std::vector<double> redistribution_potential(const std::vector<Vec3>& x) const;

 private:
  InterfaceMesh surface_;
  InterfaceTrackerSettings settings_;
  std::vector<double> initial_areas_;
  double initial_area_ = 0.0;
  std::vector<Vec3> x_;           // x_n
  std::vector<Vec3> x_previous_;  // x_{n-1}
  Vec3 centre_ = Vec3::Zero();           // X_n
  Vec3 centre_previous_ = Vec3::Zero();  // X_{n-1}
  int steps_ = 0;
  int centre_steps_ = 0;
  double last_dt_ = 0.0;  // t_n - t_{n-1}
};

}  // namespace softflow::physics
