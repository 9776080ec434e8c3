// When a run remeshes ([remesh], issue 31): before a step, once the worst
// element is below remesh.quality, once remesh.interval has passed since the
// last remesh, or once an object's gap to a wall or another object is
// crossed by fewer than remesh.gap_elements elements. A remesh that leaves
// its trigger's condition standing (the remesher's best mesh of this shape
// is below the quality, a gap it cannot widen in elements) or that fails is
// not tried again before every step: that trigger waits for a further 5 %
// drop (measured: a migrating particle remeshed at 60 steps in a row).
#pragma once

#include <limits>
#include <optional>
#include <string>

#include "softflow/io/case_config.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::simulation {

/// The state of the mesh a trigger reads.
struct MeshCondition {
  double time = 0.0;
  double quality = 1.0;  ///< mesh::min_quality
  /// Elements across the least-resolved narrow gap (geometry::least_resolved_gap),
  /// +infinity when no gap is narrower than the mesher refines.
  double gap_elements = std::numeric_limits<double>::infinity();
  std::string gap_description;  ///< e.g. "object 1 to the upper wall"
};

class RemeshTriggers {
 public:
  explicit RemeshTriggers(const io::CaseConfig& config);

  /// The condition of `mesh` at `time` with worst quality `quality`; the gap
  /// is measured only when remesh.gap_elements is set (it costs a pass over
  /// the tetrahedra near each narrow gap).
  [[nodiscard]] MeshCondition measure(const mesh::Mesh& mesh, double time, double quality) const;

  /// Why the run must remesh now ("" if it need not), given the time of the
  /// last remesh (0 before the first).
  [[nodiscard]] std::string due(const MeshCondition& now, double last_remesh_time) const;

  /// After a remesh that succeeded, with the new mesh's condition.
  void remeshed(const MeshCondition& after);
  /// After a remesh that failed, with the condition it left unchanged.
  void failed(const MeshCondition& before);

 private:
  io::RemeshConfig settings_;
  double narrow_gap_ = 0.0;  ///< gaps narrower than this are measured
  double quality_fell_short_at_ = std::numeric_limits<double>::infinity();
  double gap_fell_short_at_ = std::numeric_limits<double>::infinity();
};

}  // namespace softflow::simulation
