// Checkpoints: the full state of a run in time, as one HDF5 file written atomically.
#pragma once

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "softflow/mesh/mesh.hpp"

namespace softflow::io {

/// Bumped whenever the layout below changes; a checkpoint of another format
/// version is refused rather than misread.
inline constexpr int kCheckpointFormatVersion = 2;

/// One interface's tracking history: what BDF2 and the centre-velocity
/// formula need besides the current positions (thesis eqs. 2.49-2.52).
struct CheckpointObject {
  std::vector<mesh::Point> x;                         ///< x_n
  std::vector<mesh::Point> x_previous;                ///< x_{n-1}
  mesh::Point centre = mesh::Point::Zero();           ///< X_n
  mesh::Point centre_previous = mesh::Point::Zero();  ///< X_{n-1}
  int steps = 0;         ///< corrections done (BDF1 at the first, BDF2 after)
  int centre_steps = 0;  ///< centre velocities computed
  mesh::Point last_centre_velocity = mesh::Point::Zero();
};

/// Everything a run in time needs to continue as if never stopped.
///
/// File layout (HDF5; every array row-major, points as n x 3 doubles):
///   /                 attributes format = "softflow-checkpoint", format_version,
///                     softflow_version, case_toml, run_json, step, time, dt,
///                     translation_x, refactor_next, n_factorizations,
///                     analysis_step, factorization_step
///   /mesh/            the reference (initial) mesh: box, nodes, is_vertex, tets,
///                     tet_region, boundary_faces, boundary_face_tag,
///                     interface_faces, interface_object, periodic_master
///   /state/nodes      the moved mesh's node positions at t_n
///   /state/previous_nodes, /state/mesh_velocity   at t_{n-1}; u_m of the last step
///   /state/solution   velocity and pressure at t_n (every dof)
///   /state/previous_nodes, /state/mesh_velocity   at t_{n-1}; u_m of the last step
///   /state/analysis_nodes, /state/factorization_nodes   see below
///   /state/ale_reference_nodes   where the ALE operator was built; attributes
///                     ale_rebuilt_at_quality, ale_rebuilds (format version 2)
///   /objects/<k>/     x, x_previous, centre, centre_previous,
///                     last_centre_velocity; attributes steps, centre_steps
struct Checkpoint {
  std::string softflow_version;
  int format_version = kCheckpointFormatVersion;
  std::string case_toml;  ///< the resolved case (io::to_toml) the run was started with
  std::string run_json;   ///< the run's own bookkeeping (totals for the summary), opaque here

  int step = 0;
  double time = 0.0;
  double dt = 0.0;
  double translation_x = 0.0;  ///< the mesh's accumulated translation with the drop (Step 2)

  mesh::Mesh reference_mesh;       ///< the initial mesh: a restart does not re-mesh
  /// Where the mesh-motion operator was last built (the initial nodes until
  /// time.ale_rebuild_quality triggers a rebuild), and the quality then.
  std::vector<mesh::Point> ale_reference_nodes;
  double ale_rebuilt_at_quality = std::numeric_limits<double>::infinity();
  int ale_rebuilds = 0;
  std::vector<mesh::Point> nodes;  ///< the moved mesh at t_n
  std::vector<mesh::Point>
      previous_nodes;  ///< at t_{n-1}, for the BDF2 mesh velocity (empty at step 0)
  std::vector<mesh::Point> mesh_velocity;  ///< u_m over the last step
  std::vector<double> solution;

  /// The direct solver's preconditioner: the mesh nodes of its symbolic
  /// analysis (the first factorisation) and of the factors in use, so that a
  /// restart rebuilds the very same factors (empty: none built yet).
  std::vector<mesh::Point> analysis_nodes;
  std::vector<mesh::Point> factorization_nodes;
  int analysis_step = 0;  ///< the steps whose solves built them
  int factorization_step = 0;
  bool refactor_next = false;
  int n_factorizations = 0;

  std::vector<CheckpointObject> objects;
};

/// Writes `checkpoint` to `path` atomically: into `<path>.tmp-<pid>`, flushed
/// to disk, then renamed over `path`. A crash at any moment leaves the
/// previous checkpoint intact. Throws softflow::Error.
void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);

/// Reads a checkpoint; throws InputError naming the file if it is missing,
/// not a softflow checkpoint, of another format version, or damaged.
Checkpoint read_checkpoint(const std::filesystem::path& path);

}  // namespace softflow::io
