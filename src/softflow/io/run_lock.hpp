// One writer per output directory: an advisory lock held for a run's whole life.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "softflow/common/error.hpp"

namespace softflow::io {

/// Another softflow process is writing the output directory (issue 33):
/// reported with exit code 4, nothing touched.
class DirectoryBusy : public Error {
 public:
  using Error::Error;
};

/// Who holds a RunLock, as its lock file records it.
struct LockHolder {
  long pid = 0;
  std::string host;
  std::string command;  ///< e.g. "run", "restart", "sweep"
};

/// An exclusive lock on an output directory, held from before meshing until
/// the process ends, so that no two softflow processes ever write one
/// directory (two `run`s, a `run` and a `restart`, two `sweep`s).
///
/// The lock is flock(2) on the sibling file `<dir>.lock`, not a file inside
/// the directory: a run replaces its directory as a whole (OutputDirectory),
/// which would take a lock inside it along. The kernel releases the lock
/// when the holder dies however it dies (SIGKILL, out of memory), so a stale
/// lock cannot exist on this host; a holder on another host is seen through
/// the lock as far as the file system carries flock (NFS does) and, for a
/// run, through progress.json (simulation::refuse_to_replace_unfinished_run).
///
/// The file records the holder's pid, host and command for the message of
/// the process refused. It is removed on release; acquiring checks that the
/// file locked is still the one under the name, so a release racing an
/// acquire never leaves two holders.
class RunLock {
 public:
  /// Takes the lock of `directory` or throws DirectoryBusy naming the holder
  /// (Error if the lock file cannot be created, e.g. no permission).
  RunLock(const std::filesystem::path& directory, const std::string& command);
  ~RunLock();
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

  [[nodiscard]] const std::filesystem::path& lock_file() const { return lock_file_; }

  /// Whether a live process holds the lock of `directory` now, and who (as
  /// recorded; pid 0 if the holder has not written its record yet).
  static std::optional<LockHolder> holder(const std::filesystem::path& directory);

 private:
  std::filesystem::path lock_file_;
  std::vector<std::filesystem::path> created_;  ///< parents made for the lock, innermost first
  int fd_ = -1;
};

/// `<directory>.lock`, with a trailing separator of `directory` ignored.
std::filesystem::path lock_file_of(const std::filesystem::path& directory);

}  // namespace softflow::io
