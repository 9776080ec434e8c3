// Transport of a (multi-component) field by the flow in the ALE frame, with
// SUPG and BDF1/BDF2: the equation the log-conformation tensor obeys.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "softflow/common/state.hpp"
#include "softflow/fem/field.hpp"
#include "softflow/time/bdf.hpp"

namespace softflow::fem {
class MeshTransfer;
}  // namespace softflow::fem

namespace softflow::physics {

/// The SUPG parameter's time scale (fem/supg.hpp): `steady` is h / (2 |w|)
/// whatever the step (the thesis's), `transient` limits it to dt / 2.
enum class SupgTau { steady, transient };

/// Advances a field s with any number of components on a scalar space (P1
/// per region for the log-conformation tensor, thesis §2.3.2) through
///
///   ds/dt|_mesh + w . grad s = r,       w = u - u_m,
///
/// where d/dt|_mesh is the time derivative at a moving mesh node (so the
/// old nodal values are simply the previous ones) and r a source evaluated
/// at quadrature points by the caller (for the log-conformation: the
/// Fattal-Kupferman terms, from the latest s and grad u). In time BDF1 at
/// the first step, BDF2 after (time::bdf, eqs. 2.47-2.50's Gear scheme); in
/// space SUPG, test functions v + tau w . grad v with tau = h / (2 |w|)
/// (SPEC §2 part 5, fem::supg_tau without diffusion), or, per region,
/// combined with dt / 2 (SupgTau::transient, fem::transient_supg_tau).
///
/// The operator (a0/dt) M + C(w) + SUPG is the same for every component:
/// it is assembled once per step (la::CsrMatrix; non-symmetric), factored
/// once (MUMPS LU) and solved for each component. No boundary conditions
/// are needed where w . n = 0 (walls moving tangentially, periodic faces,
/// interfaces the mesh follows); inflow values can be imposed with
/// `set_dirichlet`.
///
/// The BDF history s_{n-1} lives here and is part of the run's state
/// (state_part()).
class AleTransport {
 public:
  using Source = std::function<fem::PointValue(const fem::QuadraturePoint&)>;
  /// Values g(x, region) imposed at the constrained nodes after each step.
  using BoundaryValues = std::function<Eigen::VectorXd(const Eigen::Vector3d&, int region)>;

  /// `s` is the transported field (its space and components); it must
  /// outlive this object.
  /// `tau_by_region[r]`: the SUPG parameter's kind in region r (0 the
  /// matrix, k object k); steady where not given.
  explicit AleTransport(fem::Field& s, std::vector<SupgTau> tau_by_region = {});
  ~AleTransport();
  AleTransport(const AleTransport&) = delete;
  AleTransport& operator=(const AleTransport&) = delete;

  /// Constrains the dofs at these mesh nodes (every copy, every component)
  /// to g(x, region, t_{n+1}) at each step; e.g. an inflow boundary.
  void set_dirichlet(std::vector<int> nodes, std::function<Eigen::VectorXd(
                                                 const Eigen::Vector3d&, int region, double t)> g);

  /// One step of length dt to time t_new: s (at t_n on entry) becomes
  /// s_{n+1}. `u` and `mesh_velocity` are vector fields (3 components) on
  /// the current (moved) mesh; `source` may be empty. dt may differ from
  /// the previous step's: BDF2 then takes its variable-step coefficients
  /// (time::bdf). Collective.
  void step(const fem::Field& u, const fem::Field* mesh_velocity, const Source& source, double dt,
            double t_new);

  /// Steps done since the start or the last restart_history() (BDF1 first, then BDF2).
  [[nodiscard]] int steps() const { return steps_; }
  /// t_n - t_{n-1}: the last step's length (0 before the first).
  [[nodiscard]] double last_step() const { return last_dt_; }
  /// The BDF coefficients and the extrapolation to t_{n+1} that the next
  /// step(dt) will take: for a caller that predicts s_{n+1} before the step
  /// and must predict it as the step will compute it (the D'Avino-Hulsen
  /// stress of the Stokes step, physics/stokes/viscoelastic_terms.hpp).
  [[nodiscard]] time::BdfCoefficients next_bdf(double dt) const;
  [[nodiscard]] time::Extrapolation next_extrapolation(double dt) const;
  /// The next step is BDF1 again, as the first: after a jump in the
  /// velocity (e.g. walls that stop), where BDF2's stencil would span the
  /// jump and leave an O(dt) error.
  void restart_history() { steps_ = 0; }
  /// s_{n-1} (meaningful once steps() > 0): for sources extrapolated to
  /// t_{n+1}, which keeps an explicit source second order.
  [[nodiscard]] const fem::Field& previous() const { return previous_; }
  /// During step(): the weights of s_n and s_{n-1} that extrapolate s to
  /// t_{n+1} (s_n alone at a first step; 2 s_n - s_{n-1} at a constant step).
  [[nodiscard]] const time::Extrapolation& step_extrapolation() const { return extrapolation_; }
  /// After a remesh: the history of `old`, the transport of the same field
  /// on the old mesh (s_{n-1} through `transfer`, the step count, the last
  /// step), so that BDF2 goes on across the remesh. Collective.
  void carry_over(const AleTransport& old, const fem::MeshTransfer& transfer);
  /// The history as a part of the run's state: "transport/<field name>".
  [[nodiscard]] StatePart state_part();

 private:
  /// t_n - t_{n-1}, or dt where no step is known.
  [[nodiscard]] double previous_step(double dt) const;

  fem::Field& s_;
  std::vector<SupgTau> tau_by_region_;
  fem::Field previous_;  // s_{n-1}
  fem::Field scalar_;    // one component's solution
  fem::ElementMatrix operator_;  // on scalar_'s dofs
  std::vector<int> constrained_scalar_dofs_;  // owned, scalar numbering
  std::function<Eigen::VectorXd(const Eigen::Vector3d&, int, double)> boundary_values_;
  int steps_ = 0;
  double last_dt_ = 0.0;  // t_n - t_{n-1}
  time::Extrapolation extrapolation_;
};

}  // namespace softflow::physics
