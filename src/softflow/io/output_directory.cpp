#include "softflow/io/output_directory.hpp"

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::io {

namespace fs = std::filesystem;

namespace {

/// `path` with `suffix` appended to its last component ("out/a" -> "out/a.partial-12").
fs::path with_suffix(const fs::path& path, std::string_view suffix) {
  fs::path p = path;
  p += std::string(suffix);
  return p;
}

std::string pid_suffix(std::string_view what) { return fmt::format(".{}-{}", what, ::getpid()); }

/// "out/a/" names the directory "out/a": without this the staging directory
/// would be "out/a/.partial-12", inside the directory it is meant to replace.
fs::path without_trailing_separator(fs::path directory) {
  if (!directory.has_filename() && directory.has_parent_path()) directory = directory.parent_path();
  return directory;
}

[[noreturn]] void fail(std::string_view action, const fs::path& path, const std::error_code& ec) {
  throw Error(fmt::format("cannot {} '{}': {}", action, path.string(), ec.message()));
}

/// POSIX file descriptor that closes itself.
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() { close(); }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  [[nodiscard]] int get() const { return fd_; }
  /// Returns 0 or the errno of close(), which may report a delayed write error.
  int close() {
    if (fd_ < 0) return 0;
    const int rc = ::close(fd_);
    fd_ = -1;
    return rc == 0 ? 0 : errno;
  }

 private:
  int fd_ = -1;
};

/// Writes all of `text` to a new file, flushed to disk; returns 0 or an errno.
int write_and_sync(const fs::path& path, std::string_view text) {
  FileDescriptor file(::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
  if (file.get() < 0) return errno;
  const char* data = text.data();
  std::size_t left = text.size();
  while (left > 0) {
    const ssize_t n = ::write(file.get(), data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  // Without fsync, a crash soon after the rename can leave an empty file
  // under the new name on some file systems: the opposite of atomic.
  if (::fsync(file.get()) != 0) return errno;
  return file.close();
}

}  // namespace

void write_text_file_atomically(const fs::path& path, std::string_view text) {
  const fs::path tmp = with_suffix(path, pid_suffix("tmp"));
  if (const int err = write_and_sync(tmp, text); err != 0) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    fail("write", path, std::error_code(err, std::generic_category()));
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    fail("write", path, ec);
  }
}

OutputDirectory::OutputDirectory(fs::path directory, bool is_writer)
    : directory_(without_trailing_separator(std::move(directory))), is_writer_(is_writer) {
  const auto name = directory_.filename();
  if (directory_.empty() || name == "." || name == "..")
    throw InputError(
        fmt::format("output directory '{}': must name a directory to create", directory_.string()));
  staging_ = with_suffix(directory_, pid_suffix("partial"));
  if (!is_writer_) return;

  std::error_code ec;
  if (directory_.has_parent_path()) {
    fs::create_directories(directory_.parent_path(), ec);
    if (ec) fail("create the directory", directory_.parent_path(), ec);
  }
  // Leftovers of runs into this directory that were killed before their
  // commit (SIGKILL, a second stop request): never results, and the caller
  // holds the directory's lock, so no live run is writing any of them.
  const std::string prefix = directory_.filename().string() + ".partial-";
  const fs::path parent = directory_.has_parent_path() ? directory_.parent_path() : fs::path(".");
  for (const auto& entry : fs::directory_iterator(parent, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    fs::remove_all(entry.path(), ec);
    if (ec) fail("remove the stale directory", entry.path(), ec);
  }
  if (ec) fail("list", parent, ec);
  fs::create_directory(staging_, ec);
  if (ec) fail("create the output directory", staging_, ec);
}

OutputDirectory::~OutputDirectory() {
  if (!is_writer_ || committed_) return;
  std::error_code ignored;  // a destructor must not throw, least of all while unwinding
  fs::remove_all(staging_, ignored);
}

fs::path OutputDirectory::path_of(std::string_view file_name) const { return staging_ / file_name; }

void OutputDirectory::write_text(std::string_view file_name, std::string_view text) const {
  if (is_writer_) write_text_file_atomically(path_of(file_name), text);
}

void OutputDirectory::commit() {
  if (!is_writer_ || committed_) return;
  std::error_code ec;
  const auto status = fs::symlink_status(directory_, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) fail("inspect", directory_, ec);

  if (!fs::exists(status)) {
    fs::rename(staging_, directory_, ec);
    if (ec) fail("rename the results to", directory_, ec);
    committed_ = true;
    return;
  }
  // Only ever replace a directory: a file or link of that name is not ours to delete.
  if (!fs::is_directory(status))
    throw Error(fmt::format("cannot write results to '{}': it exists and is not a directory",
                            directory_.string()));
  const fs::path old = with_suffix(directory_, pid_suffix("old"));
  fs::remove_all(old, ec);
  fs::rename(directory_, old, ec);
  if (ec) fail("move the previous results aside from", directory_, ec);
  fs::rename(staging_, directory_, ec);
  if (ec) {
    std::error_code ignored;
    fs::rename(old, directory_, ignored);  // put the previous results back
    fail("rename the results to", directory_, ec);
  }
  committed_ = true;
  // The new results are in place; failing to delete the old ones loses nothing.
  fs::remove_all(old, ec);
}

}  // namespace softflow::io
