// Atomic output: a committed run appears whole, an aborted one leaves nothing.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "softflow/common/error.hpp"
#include "softflow/io/output_directory.hpp"

namespace softflow::io {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Names of the entries of `dir`, so a test can see that no staging,
/// temporary or moved-aside directory was left behind.
std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

/// A fresh scratch directory per test, removed afterwards.
class OutputDirectoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() /
            ("softflow_output_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
};

TEST_F(OutputDirectoryTest, CommitPublishesTheStagedFiles) {
  const fs::path dir = root_ / "runs" / "drop";
  {
    OutputDirectory out(dir, true);
    EXPECT_TRUE(fs::is_directory(out.staging_path()));
    EXPECT_NE(out.staging_path().filename().string().find("drop.partial-"), std::string::npos);
    EXPECT_FALSE(fs::exists(dir));  // nothing visible before commit
    out.write_text("summary.json", "{}\n");
    std::ofstream(out.path_of("fields.vtu")) << "vtu";
    out.commit();
    EXPECT_TRUE(out.committed());
  }
  EXPECT_EQ(read(dir / "summary.json"), "{}\n");
  EXPECT_EQ(read(dir / "fields.vtu"), "vtu");
  EXPECT_EQ(entries(root_ / "runs"), std::vector<std::string>{"drop"});
}

TEST_F(OutputDirectoryTest, AbortLeavesNothing) {
  const fs::path dir = root_ / "drop";
  try {
    OutputDirectory out(dir, true);
    out.write_text("case.toml", "x = 1\n");
    throw std::runtime_error("solver failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_TRUE(entries(root_).empty());
}

TEST_F(OutputDirectoryTest, AbortKeepsThePreviousResults) {
  const fs::path dir = root_ / "drop";
  fs::create_directories(dir);
  std::ofstream(dir / "summary.json") << "old";
  {
    OutputDirectory out(dir, true);
    out.write_text("summary.json", "new");
  }
  EXPECT_EQ(read(dir / "summary.json"), "old");
  EXPECT_EQ(entries(root_), std::vector<std::string>{"drop"});
}

TEST_F(OutputDirectoryTest, CommitReplacesAnOlderRun) {
  const fs::path dir = root_ / "drop";
  fs::create_directories(dir);
  std::ofstream(dir / "stale_file.txt") << "old";
  {
    OutputDirectory out(dir, true);
    out.write_text("summary.json", "new");
    out.commit();
    out.commit();  // a second commit does nothing
  }
  EXPECT_EQ(read(dir / "summary.json"), "new");
  EXPECT_FALSE(fs::exists(dir / "stale_file.txt"));
  EXPECT_EQ(entries(root_), std::vector<std::string>{"drop"});  // no ".old-" left
}

TEST_F(OutputDirectoryTest, StagingLeftByKilledRunsIsRemovedAndOnlyItsOwn) {
  // A run killed before its commit (SIGKILL, a second SIGTERM) leaves its
  // staging directory; the next run into the same directory removes it,
  // and touches neither another directory's staging nor moved-aside results.
  const fs::path dir = root_ / "drop";
  for (const char* left : {"drop.partial-12345", "drop.partial-7"}) {
    fs::create_directories(root_ / left);
    std::ofstream(root_ / left / "summary.json") << "half";
  }
  fs::create_directories(root_ / "drops.partial-12345");
  fs::create_directories(root_ / "drop.old-12345");
  {
    OutputDirectory out(dir, true);
    out.write_text("summary.json", "new");
    out.commit();
  }
  EXPECT_EQ(entries(root_),
            (std::vector<std::string>{"drop", "drop.old-12345", "drops.partial-12345"}));
  EXPECT_EQ(read(dir / "summary.json"), "new");
}

TEST_F(OutputDirectoryTest, TrailingSeparatorNamesTheSameDirectory) {
  {
    OutputDirectory out((root_ / "drop").string() + "/", true);
    EXPECT_EQ(out.staging_path().parent_path(), root_);
    out.commit();
  }
  EXPECT_TRUE(fs::is_directory(root_ / "drop"));
}

TEST_F(OutputDirectoryTest, NonWriterTouchesNothing) {
  const fs::path dir = root_ / "drop";
  {
    OutputDirectory out(dir, false);
    EXPECT_FALSE(out.is_writer());
    out.write_text("summary.json", "{}");
    out.commit();
  }
  EXPECT_TRUE(entries(root_).empty());
}

TEST_F(OutputDirectoryTest, RefusesToReplaceAFile) {
  const fs::path dir = root_ / "drop";
  std::ofstream(dir) << "not a directory";
  {
    OutputDirectory out(dir, true);
    EXPECT_THROW(out.commit(), Error);
  }
  EXPECT_EQ(read(dir), "not a directory");
  EXPECT_EQ(entries(root_), std::vector<std::string>{"drop"});  // staging removed
}

TEST_F(OutputDirectoryTest, RejectsDirectoriesItCannotCreate) {
  EXPECT_THROW(OutputDirectory("", true), InputError);
  EXPECT_THROW(OutputDirectory(root_ / "..", true), InputError);
}

TEST_F(OutputDirectoryTest, AtomicTextFileReplacesContentAndLeavesNoTemporary) {
  const fs::path file = root_ / "checkpoint.txt";
  write_text_file_atomically(file, "first");
  write_text_file_atomically(file, "second");
  EXPECT_EQ(read(file), "second");
  EXPECT_EQ(entries(root_), std::vector<std::string>{"checkpoint.txt"});
}

TEST_F(OutputDirectoryTest, AtomicTextFileReportsAMissingFolder) {
  EXPECT_THROW(write_text_file_atomically(root_ / "no_such_dir" / "f.txt", "x"), Error);
  EXPECT_TRUE(entries(root_).empty());
}

}  // namespace
}  // namespace softflow::io
