// The objects' interfaces in a run: one InterfaceTracker per object and what
// the stages of a step do with them (thesis §2.3.3, Steps 1, 2 and 5), their
// measures, their checkpointed state and their carry-over to a new mesh.
// DropSimulation holds one and hands it the fluid velocity at interface nodes;
// it knows nothing of the Stokes dofs, the mesh motion or the modules.
#pragma once

#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "softflow/common/state.hpp"
#include "softflow/geometry/interface_surface.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/mesh/mesh.hpp"
#include "softflow/physics/ale/moving_mesh.hpp"
#include "softflow/physics/interface/interface_tracker.hpp"
#include "softflow/physics/stokes/stokes_problem.hpp"

namespace softflow::simulation {

/// Below this D an object is a sphere to round-off and its orientation is
/// undefined: ObjectState::theta_deg is NaN.
inline constexpr double kOrientationUndefinedBelow = 1e-8;

/// What is recorded for one object at one time.
struct ObjectState {
  int object = 0;
  double deformation = 0.0, theta_deg = 0.0, L = 0.0, B = 0.0, W = 0.0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d centre_velocity = Eigen::Vector3d::Zero();
  double volume = 0.0, area = 0.0, ellipsoid_deviation = 0.0;
};

/// The fluid velocity at interface node `node` (a volume node) of object
/// `object` (1-based), from the last Stokes solution.
using InterfaceVelocity = std::function<physics::Vec3(int node, int object)>;

/// Per object, the interface positions of one time level.
using InterfacePositions = std::vector<std::vector<physics::Vec3>>;

class ObjectInterfaces {
 public:
  /// The trackers of every object of `mesh` at its current positions.
  ObjectInterfaces(const io::CaseConfig& config, const mesh::Mesh& mesh);

  [[nodiscard]] std::size_t size() const { return trackers_.size(); }
  [[nodiscard]] std::span<const physics::InterfaceTracker> trackers() const { return trackers_; }

  /// Step 1: x_hat_{n+1} = 2 x_n - x_{n-1} (eq. 2.49; x_n at a BDF1 step).
  [[nodiscard]] InterfacePositions predict(double dt) const;
  /// Step 2: each centre of volume's velocity U at t_{n+1} from the predicted
  /// surface (eqs. 2.51-2.54), recorded; `x_shift` the move of the single
  /// object's centre along x (the mesh follows it, d1), 0 with several.
  std::vector<physics::Vec3> advance_centres(const InterfacePositions& x_hat, double dt, double& x_shift);
  /// Where Step 3 puts the interface nodes.
  [[nodiscard]] std::vector<physics::InterfacePlacement> placements(const InterfacePositions& x_hat) const;
  /// The data of the semi-implicit tension (physics::SemiImplicitTension) for
  /// the interfaces at x_hat; empty unless interface.semi_implicit_tension.
  [[nodiscard]] physics::SemiImplicitTension semi_implicit_tension(const InterfacePositions& x_hat, double dt,
                                                                   int n_mesh_nodes,
                                                                   const InterfaceVelocity& velocity) const;
  /// Step 5: x_{n+1} from the SUPG surface convection equation (eq. 2.50).
  void correct(const InterfacePositions& x_hat, const std::vector<physics::Vec3>& centre_velocity,
               double dt, const InterfaceVelocity& velocity);
  /// Whether the last predict extrapolated (false at a BDF1 step).
  [[nodiscard]] bool extrapolating() const;
  /// StepReport::interface_change of the corrected interfaces against x_hat.
  [[nodiscard]] double interface_change(const InterfacePositions& x_hat) const;
  /// BDF1 again (after a jump in the wall speed).
  void restart_histories();
  /// Records the centre velocities of the step just taken (reported by measure).
  void set_last_centre_velocity(std::vector<physics::Vec3> velocity) { last_centre_velocity_ = std::move(velocity); }
  [[nodiscard]] const std::vector<physics::Vec3>& last_centre_velocity() const { return last_centre_velocity_; }

  /// Object k's (0-based) deformation, orientation, centre, volume, area.
  [[nodiscard]] ObjectState measure(int k, const physics::Vec3& centre_velocity) const;
  /// Each object's volume at t = 0 (the reference for the volume drift).
  [[nodiscard]] const std::vector<double>& initial_volumes() const { return initial_volumes_; }
  void set_initial_volumes(std::vector<double> volumes);
  /// Throws AccuracyError (step, object, drift, what to try) past time.max_volume_drift.
  void check_volumes(int step, double time) const;

  /// One checkpoint part per object ("objects/<k>"): histories, the last
  /// centre velocity, the redistribution's reference areas.
  [[nodiscard]] std::vector<StatePart> state_parts();

  /// Takes over `old`'s state on a new mesh. Object k's interface, if
  /// kept (resampled[k] == 0), has the old nodes (new_node_of_old):
  /// histories remapped node for node, the redistribution's reference areas
  /// triangle by triangle. If resampled, its nodes are new and lie on the
  /// old surface where old_surface_point (per new mesh node) says: x_{n-1}
  /// is the old x_{n-1} interpolated there on the old curved triangles, so
  /// BDF2 goes on (restarting at BDF1 instead moved a drop's D by 1.4 % four
  /// steps later, measured); the reference areas of eq. 2.32 are the new
  /// triangles' own. Returns the largest relative change of an enclosed
  /// volume (round-off).
  double carry_over(const ObjectInterfaces& old, std::span<const int> new_node_of_old,
                    std::span<const char> resampled,
                    std::span<const geometry::InterfaceSurface::Origin> old_surface_point);

 private:
  const io::CaseConfig& config_;
  std::vector<physics::InterfaceTracker> trackers_;
  std::vector<physics::Vec3> last_centre_velocity_;
  std::vector<double> initial_volumes_;
};

}  // namespace softflow::simulation
