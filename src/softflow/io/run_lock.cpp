#include "softflow/io/run_lock.hpp"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <sstream>
#include <thread>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

namespace softflow::io {

namespace fs = std::filesystem;

namespace {

std::string this_host() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "";
  return name;
}

/// The record "pid host command" of an open lock file; pid 0 if empty or unreadable.
LockHolder read_record(int fd) {
  std::string text(512, '\0');
  const ssize_t n = ::pread(fd, text.data(), text.size(), 0);
  LockHolder holder;
  if (n <= 0) return holder;
  text.resize(static_cast<std::size_t>(n));
  std::istringstream in(text);
  in >> holder.pid >> holder.host >> holder.command;
  return holder;
}

std::string describe(const LockHolder& h) {
  if (h.pid <= 0) return "another softflow process (starting up)";
  const std::string where =
      h.host == this_host() ? "on this host" : fmt::format("on host '{}'", h.host);
  return fmt::format("`softflow {}` (pid {} {})", h.command.empty() ? "?" : h.command, h.pid,
                     where);
}

[[noreturn]] void fail(const std::string& action, const fs::path& path, int err) {
  throw Error(fmt::format("cannot {} '{}': {}", action, path.string(), std::strerror(err)));
}

}  // namespace

fs::path lock_file_of(const fs::path& directory) {
  fs::path d = directory;
  if (!d.has_filename() && d.has_parent_path()) d = d.parent_path();
  d += ".lock";
  return d;
}

RunLock::RunLock(const fs::path& directory, const std::string& command)
    : lock_file_(lock_file_of(directory)) {
  // The parents the lock needs; those made here go again with the lock if
  // still empty, so that a run refused later (bad input) leaves nothing.
  std::error_code ec;
  for (fs::path p = lock_file_.parent_path(); !p.empty() && !fs::exists(p, ec); p = p.parent_path())
    created_.push_back(p);
  if (lock_file_.has_parent_path()) {
    fs::create_directories(lock_file_.parent_path(), ec);
    if (ec) fail("create the directory", lock_file_.parent_path(), ec.value());
  }
  // A holder() query takes the lock shared for a moment: a few retries keep
  // such a query from refusing a run. A real holder is still there after them.
  constexpr int kAttempts = 6;
  for (int attempt = 0;; ++attempt) {
    const int fd = ::open(lock_file_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) fail("create the lock file", lock_file_, errno);
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      const LockHolder holder = read_record(fd);
      ::close(fd);
      if (err != EWOULDBLOCK) fail("lock", lock_file_, err);
      if (attempt + 1 < kAttempts) {
        std::this_thread::sleep_for(std::chrono::milliseconds(25));
        continue;
      }
      throw DirectoryBusy(fmt::format(
          "output directory '{}' is being written by {}: two runs in one directory would mix "
          "and lose results. Wait for it to finish, stop it ({}it checkpoints and "
          "`softflow restart` continues it), or give this run another directory ([output] "
          "directory or -o). The lock is {}; it goes when its holder ends",
          directory.string(), describe(holder),
          holder.pid > 0 ? fmt::format("kill -TERM {}: ", holder.pid) : std::string(),
          lock_file_.string()));
    }
    // The holder we waited for may have removed the file between our open
    // and our lock: then we hold a lock nobody else can see. Lock the file
    // that is under the name now instead.
    struct stat opened {}, named {};
    if (::fstat(fd, &opened) != 0 || ::stat(lock_file_.c_str(), &named) != 0 ||
        opened.st_ino != named.st_ino || opened.st_dev != named.st_dev) {
      ::close(fd);
      continue;
    }
    fd_ = fd;
    break;
  }
  const std::string record = fmt::format("{} {} {}\n", static_cast<long>(::getpid()), this_host(),
                                         command.empty() ? "?" : command);
  if (::ftruncate(fd_, 0) != 0 ||
      ::pwrite(fd_, record.data(), record.size(), 0) != static_cast<ssize_t>(record.size())) {
    const int err = errno;
    ::unlink(lock_file_.c_str());
    ::close(fd_);
    fd_ = -1;
    fail("write the lock file", lock_file_, err);
  }
}

RunLock::~RunLock() {
  if (fd_ < 0) return;
  // Unlink while still holding: a process that opened the old file meanwhile
  // sees it gone after locking it and retries on a fresh one.
  ::unlink(lock_file_.c_str());
  ::close(fd_);
  std::error_code ignored;  // fails, harmlessly, once a directory holds results
  for (const auto& d : created_) fs::remove(d, ignored);
}

std::optional<LockHolder> RunLock::holder(const fs::path& directory) {
  const fs::path file = lock_file_of(directory);
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  std::optional<LockHolder> out;
  if (::flock(fd, LOCK_SH | LOCK_NB) != 0) {
    if (errno == EWOULDBLOCK) out = read_record(fd);
  } else {
    ::flock(fd, LOCK_UN);
  }
  ::close(fd);
  return out;
}

}  // namespace softflow::io
