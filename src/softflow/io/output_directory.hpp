// Atomic run output: files are staged in <dir>.partial-<pid> and appear under <dir> only on
// commit().
#pragma once

#include <filesystem>
#include <string_view>

namespace softflow::io {

/// A run's output directory that is either complete or absent.
///
/// The constructor creates the staging directory `<dir>.partial-<pid>` (and
/// the parents of `<dir>`), after removing every `<dir>.partial-*` left by
/// runs killed before their commit: the caller must hold `<dir>`'s
/// io::RunLock, so that none of them is being written. The run writes its
/// files there (staging_path(), write_text()). commit() renames the staging
/// directory to `<dir>`; an existing `<dir>` from an earlier run is first
/// moved aside to `<dir>.old-<pid>`, then deleted, so a crash at any moment leaves either
/// the old or the new results, never a mixture. If the object is destroyed
/// without commit() (an exception unwinding the run), the staging directory
/// is removed: nothing half-written is left behind.
///
/// Only the writer (MPI rank 0) touches the file system; on other ranks every
/// member is a no-op, so all ranks may run the same code.
///
/// Errors of the file system throw softflow::Error; an unusable directory
/// name ("", ".", "..") throws InputError. Only the writer can throw, so a
/// caller running on several ranks must share the failure itself.
class OutputDirectory {
 public:
  OutputDirectory(std::filesystem::path directory, bool is_writer);
  ~OutputDirectory();
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

  /// Where the results will be after commit().
  [[nodiscard]] const std::filesystem::path& directory() const { return directory_; }
  /// Where to write now, until commit().
  [[nodiscard]] const std::filesystem::path& staging_path() const { return staging_; }
  /// staging_path() / file_name.
  [[nodiscard]] std::filesystem::path path_of(std::string_view file_name) const;
  [[nodiscard]] bool is_writer() const { return is_writer_; }
  [[nodiscard]] bool committed() const { return committed_; }

  /// Writes staging_path()/file_name (writer only).
  void write_text(std::string_view file_name, std::string_view text) const;

  /// Publishes the staged files as directory(), replacing an older one.
  /// Calling it again does nothing.
  void commit();

 private:
  std::filesystem::path directory_;
  std::filesystem::path staging_;
  bool is_writer_ = false;
  bool committed_ = false;
};

/// Writes `text` to `<path>.tmp-<pid>`, flushes it to disk and renames it to
/// `path`: readers see the old file or the new one, never a truncated one.
/// Throws softflow::Error.
void write_text_file_atomically(const std::filesystem::path& path, std::string_view text);

}  // namespace softflow::io
