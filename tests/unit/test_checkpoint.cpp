// Checkpoints: an exact round trip through HDF5, atomic replacement, and refusal of files
// that are not checkpoints of this format or of this softflow version.
#include <filesystem>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/io/checkpoint.hpp"
#include "softflow/mesh/structured_box.hpp"
#include "softflow/simulation/drop_run.hpp"

namespace softflow::io {
namespace {

namespace fs = std::filesystem;

fs::path fresh_directory(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / fmt::format("softflow_test_{}_{}", name, ::getpid());
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// A checkpoint whose every number differs, with values that do not round-trip through text.
Checkpoint sample() {
  Checkpoint c;
  c.softflow_version = SOFTFLOW_VERSION;
  c.case_toml = "[case]\nname = \"x\"\n";
  c.run_json = "{\"a\": 1}";
  c.step = 17;
  c.time = 0.1 * 17;
  c.reference_mesh = mesh::structured_box({2.0, 1.0, 1.5, true, false}, 2, 1, 2);
  c.reference_mesh.n_objects = 1;
  std::vector<mesh::Point> nodes;
  for (auto& x : c.reference_mesh.nodes)
    nodes.push_back(x * (1.0 + 1e-13) + mesh::Point::Constant(M_PI));
  c.state.set("time_loop/nodes", nodes);
  c.state.set("time_loop/translation_x", 1.0 / 3.0);
  c.state.set("time_loop/step", 17);
  c.state.set("time_loop/solution", std::vector<double>{1.0 / 7.0, -2e-300, 3e300, 0.0});
  c.state.set("time_loop/empty", std::vector<double>{});
  c.state.set("stokes/refactor_next", true);
  c.state.set("objects/1/x", std::vector<mesh::Point>{mesh::Point(1.0 / 3.0, 2.0, 3.0),
                                                      mesh::Point(-4.0, -5.0, 1e-17)});
  c.state.set("fields/tracer/values", std::vector<double>{1, 2, 3, 4, 5, 6}, 2);
  return c;
}

TEST(Checkpoint, RoundTripIsExactForEveryKindOfStateEntry) {
  const auto dir = fresh_directory("roundtrip");
  const Checkpoint c = sample();
  write_checkpoint(dir / "checkpoint.h5", c);
  const Checkpoint r = read_checkpoint(dir / "checkpoint.h5");
  EXPECT_EQ(r.softflow_version, c.softflow_version);
  EXPECT_EQ(r.format_version, kCheckpointFormatVersion);
  EXPECT_EQ(r.case_toml, c.case_toml);
  EXPECT_EQ(r.run_json, c.run_json);
  EXPECT_EQ(r.step, c.step);
  EXPECT_EQ(r.time, c.time);
  ASSERT_EQ(r.state.entries().size(), c.state.entries().size());
  for (const auto& [key, entry] : c.state.entries()) {
    ASSERT_TRUE(r.state.contains(key)) << key;
    const auto& read = r.state.entries().at(key);
    EXPECT_EQ(read.kind, entry.kind) << key;
    EXPECT_EQ(read.columns, entry.columns) << key;
    EXPECT_EQ(read.values, entry.values) << key;  // bit for bit
  }
  EXPECT_EQ(r.state.get_int("time_loop/step"), 17);
  EXPECT_TRUE(r.state.get_bool("stokes/refactor_next"));
  EXPECT_EQ(r.state.get_array("fields/tracer/values", 2).size(), 6u);
  EXPECT_THROW((void)r.state.get_double("time_loop/step"), InputError);  // wrong kind
  EXPECT_THROW((void)r.state.get_int("time_loop/missing"), InputError);
  const auto &m = r.reference_mesh, &e = c.reference_mesh;
  EXPECT_EQ(m.box.length, e.box.length);
  EXPECT_EQ(m.box.periodic_z, e.box.periodic_z);
  EXPECT_EQ(m.n_objects, e.n_objects);
  EXPECT_EQ(m.nodes, e.nodes);
  EXPECT_EQ(m.is_vertex, e.is_vertex);
  EXPECT_EQ(m.tets, e.tets);
  EXPECT_EQ(m.tet_region, e.tet_region);
  EXPECT_EQ(m.boundary_faces, e.boundary_faces);
  EXPECT_EQ(m.boundary_face_tag, e.boundary_face_tag);
  EXPECT_EQ(m.interface_faces, e.interface_faces);
  EXPECT_EQ(m.periodic_master, e.periodic_master);
  fs::remove_all(dir);
}

TEST(StateRegistry, SavesAndRestoresEveryRegisteredPartUnderItsName) {
  StateRegistry registry;
  double a = 1.5;
  std::vector<double> b{1.0, 2.0};
  registry.add({"a", [&](StateRecord& r, const std::string& p) { r.set(p + "value", a); },
                [&](const StateRecord& r, const std::string& p) { a = r.get_double(p + "value"); }});
  registry.add({"b/c", [&](StateRecord& r, const std::string& p) { r.set(p + "v", b); },
                [&](const StateRecord& r, const std::string& p) { b = r.get_array(p + "v"); }});
  EXPECT_THROW(registry.add({"a", nullptr, nullptr}), Error);
  StateRecord record;
  registry.save(record);
  EXPECT_TRUE(record.contains("a/value"));
  EXPECT_TRUE(record.contains("b/c/v"));
  a = 0.0;
  b.clear();
  registry.restore(record);
  EXPECT_EQ(a, 1.5);
  EXPECT_EQ(b, (std::vector<double>{1.0, 2.0}));
}

TEST(Checkpoint, ReplacesThePreviousOneWithoutLeavingTemporaries) {
  const auto dir = fresh_directory("replace");
  Checkpoint c = sample();
  write_checkpoint(dir / "checkpoint.h5", c);
  c.step = 18;
  write_checkpoint(dir / "checkpoint.h5", c);
  EXPECT_EQ(read_checkpoint(dir / "checkpoint.h5").step, 18);
  int files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
  fs::remove_all(dir);
}

std::string read_error(const fs::path& path) {
  try {
    read_checkpoint(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Checkpoint, RefusesWhatIsNotACheckpointOfThisFormat) {
  const auto dir = fresh_directory("refuse");
  EXPECT_NE(read_error(dir / "none.h5").find("no checkpoint there"), std::string::npos);
  std::ofstream(dir / "text.h5") << "not HDF5";
  EXPECT_NE(read_error(dir / "text.h5").find("cannot read the checkpoint"), std::string::npos);
  Checkpoint c = sample();
  c.format_version = kCheckpointFormatVersion + 1;
  write_checkpoint(dir / "future.h5", c);
  EXPECT_NE(read_error(dir / "future.h5").find("format version"), std::string::npos)
      << read_error(dir / "future.h5");
  // A file cut short (a crash mid-copy) is refused, not misread.
  write_checkpoint(dir / "whole.h5", sample());
  fs::copy_file(dir / "whole.h5", dir / "cut.h5");
  fs::resize_file(dir / "cut.h5", fs::file_size(dir / "whole.h5") / 2);
  EXPECT_NE(read_error(dir / "cut.h5").find("cannot read the checkpoint"), std::string::npos);
  fs::remove_all(dir);
}

TEST(Checkpoint, RestartRefusesAnotherSoftflowVersion) {
  const auto dir = fresh_directory("version");
  const CaseConfig config = parse_case("[time]\nend = 1.0\n", "case.toml");
  Checkpoint c = sample();
  c.softflow_version = "0.0.1-old";
  c.case_toml = to_toml(config);
  write_checkpoint(dir / simulation::kCheckpointFile, c);
  try {
    simulation::restart_drop_case(config, dir, {});
    FAIL() << "a checkpoint of another version was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("written by softflow 0.0.1-old"), std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

/// Flips one byte of `path` inside the first occurrence of the 8 bytes of `marker`.
bool flip_byte_inside(const fs::path& path, double marker) {
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  char pattern[sizeof(double)];
  std::memcpy(pattern, &marker, sizeof(double));
  const auto at = bytes.find(std::string(pattern, sizeof(double)));
  if (at == std::string::npos) return false;
  bytes[at + 3] = static_cast<char>(bytes[at + 3] ^ 0x10);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  return true;
}

TEST(Checkpoint, RefusesAFlippedByteInTheDataAsCorrupt) {
  const auto dir = fresh_directory("corrupt");
  const fs::path path = dir / "checkpoint.h5";
  write_checkpoint(path, sample());
  ASSERT_TRUE(flip_byte_inside(path, 1.0 / 7.0));  // /state/time_loop/solution[0]
  const std::string message = read_error(path);
  EXPECT_NE(message.find("corrupt checkpoint"), std::string::npos) << message;
  EXPECT_NE(message.find("checksum"), std::string::npos) << message;
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  // The mesh is checksummed too: the first node's shifted coordinate.
  write_checkpoint(path, sample());
  const double first = sample().reference_mesh.nodes.front().x();
  ASSERT_TRUE(flip_byte_inside(path, first));
  EXPECT_NE(read_error(path).find("checksum"), std::string::npos) << read_error(path);
  fs::remove_all(dir);
}

TEST(Checkpoint, RefusesADamagedAttribute) {
  const auto dir = fresh_directory("corrupt_attribute");
  const fs::path path = dir / "checkpoint.h5";
  Checkpoint c = sample();
  c.time = 1.0 / 3.0 + 1e-9;  // a value found once in the file: the time attribute
  write_checkpoint(path, c);
  ASSERT_TRUE(flip_byte_inside(path, c.time));
  const std::string message = read_error(path);
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("checksum"), std::string::npos) << message;
  fs::remove_all(dir);
}

/// A pid that no process has: a child that has exited and been reaped.
pid_t dead_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

TEST(Checkpoint, RemovesTemporariesOfDeadWritersOnly) {
  const auto dir = fresh_directory("stale");
  const fs::path path = dir / "checkpoint.h5";
  const fs::path stale = dir / fmt::format("checkpoint.h5.tmp-{}", dead_pid());
  const fs::path live = dir / fmt::format("checkpoint.h5.tmp-{}", ::getppid());
  const fs::path other = dir / fmt::format("other.h5.tmp-{}", dead_pid());
  const fs::path not_pid = dir / "checkpoint.h5.tmp-abc";
  for (const auto& f : {stale, live, other, not_pid}) std::ofstream(f) << "partial";
  write_checkpoint(path, sample());
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(other));
  EXPECT_TRUE(fs::exists(not_pid));
  EXPECT_FALSE(fs::exists(dir / fmt::format("checkpoint.h5.tmp-{}", ::getpid())));
  EXPECT_EQ(read_checkpoint(path).step, 17);
  fs::remove_all(dir);
}

TEST(RunStatus, ARunningStatusWhosePidIsDeadIsReportedAsKilled) {
  const auto dir = fresh_directory("status");
  EXPECT_EQ(simulation::run_status(dir), "");
  auto progress = [&](const std::string& status, long pid) {
    nlohmann::json j = {{"status", status}, {"step", 3}, {"pid", pid},
                        {"host", simulation::host_name()}};
    std::ofstream(dir / "progress.json") << j.dump();
  };
  progress("running", ::getpid());
  EXPECT_EQ(simulation::run_status(dir), "running");
  progress("running", dead_pid());
  EXPECT_EQ(simulation::run_status(dir), "killed");
  progress("interrupted", dead_pid());
  EXPECT_EQ(simulation::run_status(dir), "interrupted");
  // On another host the pid says nothing: still "running".
  nlohmann::json elsewhere = {{"status", "running"}, {"pid", dead_pid()}, {"host", "elsewhere."}};
  std::ofstream(dir / "progress.json") << elsewhere.dump();
  EXPECT_EQ(simulation::run_status(dir), "running");
  // The summary, written last, has the final word.
  progress("running", dead_pid());
  std::ofstream(dir / "summary.json") << R"({"status": "completed"})";
  EXPECT_EQ(simulation::run_status(dir), "completed");
  // `softflow run` refuses to replace a killed run and says so.
  fs::remove(dir / "summary.json");
  std::ofstream(dir / simulation::kCheckpointFile) << "x";
  try {
    simulation::refuse_to_replace_unfinished_run(dir);
    FAIL() << "a killed run was replaced";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("killed"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace softflow::io
