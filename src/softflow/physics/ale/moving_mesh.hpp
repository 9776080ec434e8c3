// The run's moving mesh (thesis §2.3.3, Steps 2-3): where its nodes go each step,
// the mesh velocity, and the policy that keeps the elements valid (rebuilding the
// mesh-motion operator, relocating free nodes).
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "softflow/common/state.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::mesh {
class NodeRelocation;
}  // namespace softflow::mesh

namespace softflow::physics {

class AleMeshMotion;

/// When the moving mesh repairs itself (time.ale_rebuild_quality,
/// time.relocation_quality; 0 = never).
struct MovingMeshSettings {
  /// Below this element quality the mesh-motion operator is rebuilt on the
  /// current mesh, then after each further 5 % drop.
  double rebuild_quality = 0.2;
  /// Below this element quality free nodes of the bad elements are moved.
  double relocation_quality = 0.2;
};

/// Where one object's interface nodes go: their geometry nodes and positions.
struct InterfacePlacement {
  std::span<const int> nodes;
  std::span<const Eigen::Vector3d> positions;
};

/// Moves `mesh`'s nodes each step: the translation d1 along x (Step 2), plus
/// the extension d2 of the interface displacement (eq. 2.55), plus the
/// relocations of free nodes kept since the operator's reference:
///
///   x = x_ref + relocation + d1 + d2,   interface nodes exactly where placed.
///
/// The mesh-motion operator (AleMeshMotion) lives on the reference mesh and
/// is factored once. The thesis solves the motion on the current mesh every
/// step, so that k_e = 1/V_e stiffens the elements that have shrunk; here the
/// operator is rebuilt on the current mesh when the quality falls below
/// settings.rebuild_quality, and after each further 5 % drop: the same
/// effect at a few factorisations per run. The displacement is then taken
/// from the current mesh (the new reference) and the translation restarts.
class MovingMesh {
 public:
  /// `mesh` is the run's; it must outlive this object, which moves its nodes.
  MovingMesh(mesh::Mesh& mesh, MovingMeshSettings settings);
  ~MovingMesh();
  MovingMesh(const MovingMesh&) = delete;
  MovingMesh& operator=(const MovingMesh&) = delete;

  /// Step 2: the mesh follows the objects along x by dx more (d1).
  void translate_x(double dx) { translation_x_ += dx; }
  /// Step 3: moves the mesh to the placed interfaces over a step of dt
  /// (the operator rebuilt first if the mesh has degraded); updates the mesh
  /// velocity (BDF1 at the first step or after restart_history(), BDF2
  /// after) and returns the smallest element quality of the moved mesh.
  double move(std::span<const InterfacePlacement> interfaces, double dt);
  /// The next move's mesh velocity is BDF1: after a jump of the walls.
  void restart_history() { previous_nodes_.clear(); }

  /// u_m at every geometry node over the last move (zero before any).
  [[nodiscard]] const std::vector<mesh::Point>& velocity() const { return velocity_; }
  /// The last move's dt (0 before any).
  [[nodiscard]] double last_step() const { return last_dt_; }
  /// Smallest element quality of the current mesh.
  [[nodiscard]] double quality() const { return quality_; }
  [[nodiscard]] int rebuilds() const { return rebuilds_; }
  /// Moves that relocated free nodes, and the node moves over all of them.
  [[nodiscard]] int relocation_steps() const { return relocation_steps_; }
  [[nodiscard]] int relocated_nodes() const { return relocated_nodes_; }

  /// The state a restart needs (nodes, the previous nodes, velocity, the
  /// operator's reference and warm start, relocations), as entries under
  /// `prefix`: "nodes", "previous_nodes", "mesh_velocity", "last_step",
  /// "translation_x", "ale_*", "relocation_steps", "relocated_nodes",
  /// "mesh_moves" (records from before it: their "step").
  void save(StateRecord& record, const std::string& prefix) const;
  /// `fallback_step` is taken as the last step of a record from before
  /// variable steps. Throws InputError if the record does not fit the mesh.
  void restore(const StateRecord& record, const std::string& prefix, double fallback_step);

 private:
  void rebuild_if_degraded();
  /// Relocates free nodes of `moved` below settings.relocation_quality;
  /// returns the smallest element quality of the result when it was measured
  /// on the way (relocation on), nothing otherwise.
  std::optional<double> relocate(std::vector<mesh::Point>& moved);

  mesh::Mesh& mesh_;
  MovingMeshSettings settings_;
  std::vector<mesh::Point> reference_nodes_;  // where the operator was built
  // Relocations since then: the mesh sits at reference + relocation + d1 + d2.
  std::vector<mesh::Point> relocation_;
  std::unique_ptr<mesh::NodeRelocation> relocator_;
  std::unique_ptr<AleMeshMotion> ale_;
  std::vector<mesh::Point> previous_nodes_;  // x at t_{n-1}: empty before the first move
  std::vector<mesh::Point> velocity_;
  double translation_x_ = 0.0;
  double last_dt_ = 0.0;  // t_n - t_{n-1}
  double quality_ = 1.0;
  double rebuilt_at_quality_ = std::numeric_limits<double>::infinity();
  int rebuilds_ = 0;
  int relocation_steps_ = 0;
  int relocated_nodes_ = 0;
  int moves_ = 0;  // since the start: the operator is never rebuilt before the first
};

}  // namespace softflow::physics
