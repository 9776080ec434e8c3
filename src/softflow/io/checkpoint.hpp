// Checkpoints: the full state of a run in time, as one HDF5 file written atomically.
#pragma once

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "softflow/common/state.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::io {

/// Bumped whenever the layout below changes; a checkpoint of another format
/// version is refused rather than misread. Version 3: the state is the
/// generic StateRecord of the run's registry (versions 1-2 had one
/// hand-written group per part).
inline constexpr int kCheckpointFormatVersion = 3;

/// Everything a run in time needs to continue as if never stopped.
///
/// File layout (HDF5):
///   /          attributes format = "softflow-checkpoint", format_version,
///              softflow_version, case_toml, run_json, step, time
///   /mesh/     the reference (initial) mesh: box, nodes, is_vertex, tets,
///              tet_region, boundary_faces, boundary_face_tag,
///              interface_faces, interface_object, periodic_master
///   /state/    one dataset per StateRecord entry, at its key's path
///              (e.g. /state/stokes/refactor_next, /state/objects/1/x):
///              rows x columns doubles with an attribute kind (0 integer,
///              1 real, 2 array). What is there is decided by the parts
///              registered in the run's StateRegistry, not by this file.
struct Checkpoint {
  std::string softflow_version;
  int format_version = kCheckpointFormatVersion;
  std::string case_toml;  ///< the resolved case (io::to_toml) the run was started with
  std::string run_json;   ///< the run's own bookkeeping (totals for the summary), opaque here
  int step = 0;           ///< for messages; the state has its own copy
  double time = 0.0;
  mesh::Mesh reference_mesh;  ///< the initial mesh: a restart does not re-mesh
  StateRecord state;
};

/// Writes `checkpoint` to `path` atomically: into `<path>.tmp-<pid>`, flushed
/// to disk, then renamed over `path`. A crash at any moment leaves the
/// previous checkpoint intact. Throws softflow::Error.
void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);

/// Reads a checkpoint; throws InputError naming the file if it is missing,
/// not a softflow checkpoint, of another format version, or damaged.
Checkpoint read_checkpoint(const std::filesystem::path& path);

}  // namespace softflow::io
