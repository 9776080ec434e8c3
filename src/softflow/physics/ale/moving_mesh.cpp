#include "softflow/physics/ale/moving_mesh.hpp"

#include <algorithm>
#include <utility>

#include "softflow/common/error.hpp"
#include "softflow/mesh/node_relocation.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/physics/ale/mesh_motion.hpp"
#include "softflow/physics/ale/mesh_velocity.hpp"

namespace softflow::physics {

MovingMesh::MovingMesh(mesh::Mesh& mesh, MovingMeshSettings settings)
    : mesh_(mesh),
      settings_(settings),
      reference_nodes_(mesh.nodes),
      relocation_(mesh.n_nodes(), mesh::Point::Zero()),
      relocator_(std::make_unique<mesh::NodeRelocation>(mesh)),
      ale_(std::make_unique<AleMeshMotion>(mesh)),
      velocity_(mesh.n_nodes(), mesh::Point::Zero()),
      quality_(mesh::min_quality(mesh)) {}

MovingMesh::~MovingMesh() = default;

void MovingMesh::rebuild_if_degraded() {
  const double threshold = settings_.rebuild_quality;
  if (threshold <= 0.0 || moves_ == 0 || quality_ >= threshold || quality_ >= 0.95 * rebuilt_at_quality_)
    return;
  reference_nodes_ = mesh_.nodes;
  std::fill(relocation_.begin(), relocation_.end(), mesh::Point::Zero());
  translation_x_ = 0.0;
  ale_ = std::make_unique<AleMeshMotion>(mesh_);
  rebuilt_at_quality_ = quality_;
  ++rebuilds_;
}

std::optional<double> MovingMesh::relocate(std::vector<mesh::Point>& moved) {
  // Part of this step's mesh motion, so the mesh velocity (and with it the
  // ALE transport) sees the relocation; kept in relocation_ so that later
  // steps, which extend the interface displacement from the reference
  // again, keep it too.
  const double target = settings_.relocation_quality;
  if (target <= 0.0) return std::nullopt;
  const std::vector<mesh::Point> before = moved;
  const auto report = relocator_->improve(moved, target);
  if (report.nodes_moved == 0) return report.smallest_quality;
  for (int i = 0; i < mesh_.n_nodes(); ++i) relocation_[i] += moved[i] - before[i];
  ++relocation_steps_;
  relocated_nodes_ += report.nodes_moved;
  return report.smallest_quality;
}

double MovingMesh::move(std::span<const InterfacePlacement> interfaces, double dt) {
  rebuild_if_degraded();
  // Total displacement from the reference mesh: d1 (translation) + d2, with
  // d2 = x_hat - x_ref - d1 on the interfaces and 0 on the outer boundary.
  const Eigen::Vector3d d1(translation_x_, 0.0, 0.0);
  std::vector<Eigen::Vector3d> interface_displacement(mesh_.n_nodes(), Eigen::Vector3d::Zero());
  for (const auto& placed : interfaces)
    for (std::size_t i = 0; i < placed.nodes.size(); ++i)
      interface_displacement[placed.nodes[i]] = placed.positions[i] - reference_nodes_[placed.nodes[i]] - d1;
  const auto d2 = ale_->solve(interface_displacement);
  std::vector<mesh::Point> moved(mesh_.n_nodes());
  for (int i = 0; i < mesh_.n_nodes(); ++i) moved[i] = reference_nodes_[i] + relocation_[i] + d1 + d2[i];
  for (const auto& placed : interfaces)  // exactly on the placed interface
    for (std::size_t i = 0; i < placed.nodes.size(); ++i) moved[placed.nodes[i]] = placed.positions[i];
  const auto measured = relocate(moved);
  velocity_ = bdf_mesh_velocity(moved, mesh_.nodes, previous_nodes_, dt, last_dt_);
  last_dt_ = dt;
  previous_nodes_ = std::exchange(mesh_.nodes, std::move(moved));
  quality_ = measured ? *measured : mesh::min_quality(mesh_);
  ++moves_;
  return quality_;
}

void MovingMesh::save(StateRecord& r, const std::string& p) const {
  r.set(p + "last_step", last_dt_);
  r.set(p + "translation_x", translation_x_);
  r.set(p + "nodes", mesh_.nodes);
  r.set(p + "previous_nodes", previous_nodes_);
  r.set(p + "mesh_velocity", velocity_);
  ale_->save_warm_start(r, p + "ale_");
  r.set(p + "ale_reference_nodes", reference_nodes_);
  r.set(p + "ale_rebuilt_at_quality", rebuilt_at_quality_);
  r.set(p + "ale_rebuilds", rebuilds_);
  r.set(p + "ale_relocation", relocation_);
  r.set(p + "relocation_steps", relocation_steps_);
  r.set(p + "relocated_nodes", relocated_nodes_);
  r.set(p + "mesh_moves", moves_);
}

void MovingMesh::restore(const StateRecord& r, const std::string& p, double fallback_step) {
  const auto n = mesh_.nodes.size();
  auto nodes = r.get_points(p + "nodes");
  auto previous = r.get_points(p + "previous_nodes");
  auto velocity = r.get_points(p + "mesh_velocity");
  auto reference = r.get_points(p + "ale_reference_nodes");
  if (nodes.size() != n || (!previous.empty() && previous.size() != n) ||
      (!velocity.empty() && velocity.size() != n) || reference.size() != n)
    throw InputError("the checkpoint does not fit the mesh it carries");
  moves_ = r.contains(p + "mesh_moves") ? r.get_int(p + "mesh_moves") : r.get_int(p + "step");
  // Records from before variable steps: every step was the case's.
  last_dt_ = r.contains(p + "last_step") ? r.get_double(p + "last_step")
                                         : (moves_ > 0 ? fallback_step : 0.0);
  translation_x_ = r.get_double(p + "translation_x");
  mesh_.nodes = std::move(nodes);
  previous_nodes_ = std::move(previous);
  velocity_ = velocity.empty() ? std::vector<mesh::Point>(n, mesh::Point::Zero()) : std::move(velocity);
  quality_ = mesh::min_quality(mesh_);
  rebuilt_at_quality_ = r.get_double(p + "ale_rebuilt_at_quality");
  rebuilds_ = r.get_int(p + "ale_rebuilds");
  // Records from before vertex relocation: none.
  if (r.contains(p + "ale_relocation")) {
    auto relocation = r.get_points(p + "ale_relocation");
    if (relocation.size() != n) throw InputError("the checkpoint does not fit the mesh it carries");
    relocation_ = std::move(relocation);
    relocation_steps_ = r.get_int(p + "relocation_steps");
    relocated_nodes_ = r.get_int(p + "relocated_nodes");
  } else {
    std::fill(relocation_.begin(), relocation_.end(), mesh::Point::Zero());
    relocation_steps_ = relocated_nodes_ = 0;
  }
  // The operator must be the one of the saved reference: the current one if
  // they agree (always after a fresh start; usually after a step taken
  // back), else built there again: a run that rebuilt it, or a step taken
  // back that had rebuilt it (the translation restored above counts from the
  // saved reference).
  if (reference != reference_nodes_) {
    reference_nodes_ = std::move(reference);
    mesh::Mesh rebuilt = mesh_;
    rebuilt.nodes = reference_nodes_;
    ale_ = std::make_unique<AleMeshMotion>(rebuilt);
  }
  ale_->restore_warm_start(r, p + "ale_");
}

}  // namespace softflow::physics
