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
/// hand-written group per part). Version 4: every dataset with data is
/// chunked with a Fletcher32 checksum, the attributes have a checksum of
/// their own (attributes_checksum), and the file's metadata has HDF5's.
/// Version 5: every dataset has a content hash of what was written (xxh64),
/// which also covers HDF5's chunk index (Fletcher32 does not).
inline constexpr int kCheckpointFormatVersion = 5;

/// Everything a run in time needs to continue as if never stopped.
///
/// File layout (HDF5):
///   /          attributes format = "softflow-checkpoint", format_version,
///              softflow_version, case_toml, run_json, step, time,
///              attributes_checksum (FNV-1a 64 of the attributes of the file,
///              the box's and the state entries' keys, kinds and shapes)
///   /mesh/     the reference (initial) mesh: box, nodes, is_vertex, tets,
///              tet_region, boundary_faces, boundary_face_tag,
///              interface_faces, interface_object, periodic_master
///   /state/    one dataset per StateRecord entry, at its key's path
///              (e.g. /state/stokes/refactor_next, /state/objects/1/x):
///              rows x columns doubles with an attribute kind (0 integer,
///              1 real, 2 array). What is there is decided by the parts
///              registered in the run's StateRegistry, not by this file.
///   Every dataset with data is chunked (about 1 MiB a chunk) with HDF5's
///   Fletcher32 filter; empty datasets are contiguous. Every dataset has an
///   attribute xxh64: XXH64 of its bytes as written, seeded with FNV-1a of
///   its shape (rows, columns), checked against the bytes as read.
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
/// previous checkpoint intact. Temporaries of `path` left by writers that
/// were killed are removed first. Throws softflow::Error.
void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);

/// Removes `<path>.tmp-<pid>` files whose process is gone (kill(pid, 0)
/// fails with ESRCH): what a writer killed mid-write leaves. Never the
/// current process's. A pid is only meaningful on this host.
void remove_stale_temporaries(const std::filesystem::path& path);

/// Reads a checkpoint; throws InputError naming the file if it is missing,
/// not a softflow checkpoint, of another format version, or damaged
/// ("corrupt checkpoint": a checksum or content hash that does not match,
/// or HDF5 failing on the file, naming what). What it returns is, bit for
/// bit, what write_checkpoint was given.
Checkpoint read_checkpoint(const std::filesystem::path& path);

}  // namespace softflow::io
