// One writer per output directory (issue 33): the lock, its holder, its release on death.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "softflow/io/run_lock.hpp"

namespace softflow::io {
namespace {

namespace fs = std::filesystem;

class RunLockTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("softflow_run_lock_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
};

TEST_F(RunLockTest, SecondWriterIsRefusedNamingTheHolder) {
  const fs::path dir = root_ / "out";
  const RunLock first(dir, "run");
  EXPECT_EQ(first.lock_file(), root_ / "out.lock");
  try {
    const RunLock second(dir, "restart");
    FAIL() << "a second lock of one directory was granted";
  } catch (const DirectoryBusy& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(std::to_string(::getpid())), std::string::npos) << message;
    EXPECT_NE(message.find("softflow run"), std::string::npos) << message;
    EXPECT_NE(message.find("another directory"), std::string::npos) << message;
  }
  const auto holder = RunLock::holder(dir);
  ASSERT_TRUE(holder.has_value());
  EXPECT_EQ(holder->pid, ::getpid());
  EXPECT_EQ(holder->command, "run");
}

TEST_F(RunLockTest, ReleaseRemovesTheFileAndFreesTheDirectory) {
  const fs::path dir = root_ / "out/";  // a trailing separator names the same directory
  { const RunLock lock(dir, "run"); }
  EXPECT_FALSE(fs::exists(root_ / "out.lock"));
  EXPECT_FALSE(RunLock::holder(dir).has_value());
  const RunLock again(root_ / "out", "run");
  EXPECT_TRUE(RunLock::holder(root_ / "out").has_value());
}

TEST_F(RunLockTest, AStaleLockFileIsNoLock) {
  // A file left by a holder that died between its writes: nobody holds it.
  { std::ofstream(root_ / "out.lock") << "12345 elsewhere run\n"; }
  EXPECT_FALSE(RunLock::holder(root_ / "out").has_value());
  const RunLock lock(root_ / "out", "run");
  EXPECT_EQ(RunLock::holder(root_ / "out")->pid, ::getpid());
}

TEST_F(RunLockTest, DirectoriesMadeForTheLockGoWithItWhenEmpty) {
  const fs::path dir = root_ / "a/b/out";
  { const RunLock lock(dir, "run"); EXPECT_TRUE(fs::is_directory(root_ / "a/b")); }
  EXPECT_FALSE(fs::exists(root_ / "a"));
  {
    const RunLock lock(dir, "run");
    fs::create_directories(dir);  // results written meanwhile stay, with their parents
  }
  EXPECT_TRUE(fs::is_directory(dir));
}

TEST_F(RunLockTest, TheLockDiesWithItsHolder) {
  const fs::path dir = root_ / "out";
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const RunLock lock(dir, "run");
    const char byte = 1;
    (void)!::write(ready[1], &byte, 1);
    for (;;) ::pause();  // killed by the parent, the lock still held
  }
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  try {
    const RunLock refused(dir, "run");
    FAIL() << "the lock of a live process was granted";
  } catch (const DirectoryBusy& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(child)), std::string::npos) << e.what();
  }
  ::kill(child, SIGKILL);  // no destructor, no unlink: the kernel drops the lock
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(fs::exists(root_ / "out.lock"));
  const RunLock mine(dir, "run");
  EXPECT_EQ(RunLock::holder(dir)->pid, ::getpid());
  ::close(ready[0]);
  ::close(ready[1]);
}

}  // namespace
}  // namespace softflow::io
