// Checkpoints: an exact round trip through HDF5, atomic replacement, and refusal of files
// that are not checkpoints of this format or of this softflow version.
#include <filesystem>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/common/xxh64.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/io/checkpoint.hpp"
#include "support/verification/structured_box.hpp"
#include "softflow/simulation/drop_run.hpp"
#include "softflow/simulation/run_directory.hpp"

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
  // A file cut short (a crash mid-copy) is refused as damaged, not misread.
  write_checkpoint(dir / "whole.h5", sample());
  fs::copy_file(dir / "whole.h5", dir / "cut.h5");
  fs::resize_file(dir / "cut.h5", fs::file_size(dir / "whole.h5") / 2);
  EXPECT_NE(read_error(dir / "cut.h5").find("corrupt checkpoint"), std::string::npos)
      << read_error(dir / "cut.h5");
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

TEST(Checkpoint, AParticleRunFromBeforeTheConformationKeysContinuesOnlyWithTheSteadySupgTau) {
  // Such runs carried the particle's conformation with the steady SUPG
  // parameter; the default is now transient in solids: continuing silently
  // would change the numerics half-way.
  const std::string particle =
      "[[objects]]\nmodel = \"neo_hookean\"\nmodulus = 10.0\n[time]\nend = 1.0\n";
  const auto dir = fresh_directory("conformation_keys");
  Checkpoint c = sample();
  std::string old_case = to_toml(parse_case(particle, "case.toml"));
  const std::string section =
      "\n[conformation]\nsupg_tau = \"auto\"\nstress_prediction = \"consistent\"\ndevss_g = true\n";
  ASSERT_NE(old_case.find(section), std::string::npos) << old_case;
  old_case.erase(old_case.find(section), section.size());
  ASSERT_EQ(old_case.find("supg_tau"), std::string::npos);
  c.case_toml = old_case;
  try {
    simulation::check_same_case(parse_case(particle, "case.toml"), c, dir);
    FAIL() << "the default supg_tau was accepted for a run from before the key";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "'supg_tau = \"auto\"' here, 'supg_tau = \"steady\"' in the checkpoint"),
              std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(simulation::check_same_case(
      parse_case(
          particle + "[conformation]\nsupg_tau = \"steady\"\nstress_prediction = \"euler\"\n",
          "case.toml"),
      c, dir));
  // A case without a conformation is unaffected.
  const std::string drop = "[[objects]]\n[time]\nend = 1.0\n";
  c.case_toml = to_toml(parse_case(drop, "case.toml"));
  EXPECT_NO_THROW(simulation::check_same_case(parse_case(drop, "case.toml"), c, dir));
  fs::remove_all(dir);
}

TEST(Checkpoint, ARunFromBeforeStressPredictionContinuesOnlyWithTheEulerPrediction) {
  // Such runs took the Stokes step's stress at the Euler prediction; the
  // default is now the consistent one: continuing silently would change the
  // numerics half-way.
  const std::string giesekus =
      "[matrix]\nmodel = \"giesekus\"\nsolvent_viscosity = 0.1\npolymer_viscosity = 0.9\n"
      "relaxation_time = 0.5\nmobility = 0.2\n[[objects]]\n[time]\nend = 1.0\n";
  const auto dir = fresh_directory("stress_prediction_key");
  Checkpoint c = sample();
  std::string old_case = to_toml(parse_case(giesekus, "case.toml"));
  const std::string line = "stress_prediction = \"consistent\"\n";
  ASSERT_NE(old_case.find(line), std::string::npos) << old_case;
  old_case.erase(old_case.find(line), line.size());
  c.case_toml = old_case;
  try {
    simulation::check_same_case(parse_case(giesekus, "case.toml"), c, dir);
    FAIL() << "the default stress_prediction was accepted for a run from before the key";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'stress_prediction = \"consistent\"' here, "
                                         "'stress_prediction = \"euler\"' in the checkpoint"),
              std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(simulation::check_same_case(
      parse_case(giesekus + "[conformation]\nstress_prediction = \"euler\"\n", "case.toml"), c,
      dir));
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

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Bit for bit: == would take -0.0 for 0.0, a flipped sign bit of a zero.
template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

/// Every field a checkpoint stores, bit for bit.
bool same(const Checkpoint& a, const Checkpoint& b) {
  const auto &m = a.reference_mesh, &n = b.reference_mesh;
  bool ok = a.softflow_version == b.softflow_version && a.format_version == b.format_version &&
            a.case_toml == b.case_toml && a.run_json == b.run_json && a.step == b.step &&
            std::memcmp(&a.time, &b.time, sizeof a.time) == 0 &&
            same_bytes(std::vector<double>{m.box.length, m.box.height, m.box.width},
                       std::vector<double>{n.box.length, n.box.height, n.box.width}) &&
            m.box.periodic_x == n.box.periodic_x && m.box.periodic_z == n.box.periodic_z &&
            m.n_objects == n.n_objects && same_bytes(m.nodes, n.nodes) &&
            m.is_vertex == n.is_vertex && m.tets == n.tets && m.tet_region == n.tet_region &&
            m.boundary_faces == n.boundary_faces && m.boundary_face_tag == n.boundary_face_tag &&
            m.interface_faces == n.interface_faces && m.interface_object == n.interface_object &&
            m.periodic_master == n.periodic_master &&
            a.state.entries().size() == b.state.entries().size();
  for (const auto& [key, entry] : a.state.entries()) {
    if (!ok || !b.state.contains(key)) return false;
    const auto& other = b.state.entries().at(key);
    ok = entry.kind == other.kind && entry.columns == other.columns &&
         same_bytes(entry.values, other.values);
  }
  return ok;
}

std::string list(const std::vector<std::size_t>& offsets) {
  std::string s;
  for (std::size_t i = 0; i < offsets.size() && i < 20; ++i) s += fmt::format(" {}", offsets[i]);
  return s + (offsets.size() > 20 ? " ..." : "");
}

void put_byte(const fs::path& path, std::size_t offset, char byte) {
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  file.seekp(static_cast<std::streamoff>(offset));
  file.put(byte);
}

// One bit flipped at every byte of a checkpoint (bit `offset % 8`): each read
// must give back exactly what was written or say "corrupt checkpoint";
// never other data, another message or a crash, and never leave an HDF5
// object of ours open.
//
// Before the content hashes (format 4: Fletcher32 per chunk, HDF5 1.8's file
// format), this file was 49,225 bytes and 272 offsets read as other data
// without a word (1209, 1236-1258, 6209, 6236-6242, 6252, 8636, 8662-8685, ...
// 46044-46069), every one in a v1 B-tree node of a chunk index, which no
// checksum covers (a flipped chunk offset there loses the chunk, and HDF5
// reads zeros). 17 more gave "cannot read the checkpoint" (offsets 0-7:
// the signature; 18689, 21129, 25431, ...: "missing dataset", "cannot read
// the state"), and the process printed "HDF5: infinite loop closing library"
// at exit.
TEST(Checkpoint, EveryFlippedBitIsReadIntactOrRefusedAsCorrupt) {
  const auto dir = fresh_directory("bit_flips");
  const Checkpoint written = sample();
  const fs::path damaged = dir / "damaged.h5";
  write_checkpoint(damaged, written);
  const std::string bytes = file_bytes(damaged);
  ASSERT_TRUE(same(read_checkpoint(damaged), written));
  std::vector<std::size_t> silent, other_message, left_open;
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    put_byte(damaged, at, static_cast<char>(bytes[at] ^ (1 << (at % 8))));
    try {
      if (!same(read_checkpoint(damaged), written)) silent.push_back(at);
    } catch (const InputError& e) {
      if (std::string(e.what()).find("corrupt checkpoint") == std::string::npos) {
        if (other_message.empty()) ADD_FAILURE() << "offset " << at << ": " << e.what();
        other_message.push_back(at);
      }
    }
    if (H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL) != 0) left_open.push_back(at);
    put_byte(damaged, at, bytes[at]);
  }
  EXPECT_TRUE(silent.empty()) << silent.size() << " of " << bytes.size()
                              << " flipped bits read as other data, at offsets" << list(silent);
  EXPECT_TRUE(other_message.empty())
      << other_message.size() << " gave another message, at offsets" << list(other_message);
  EXPECT_TRUE(left_open.empty()) << "HDF5 objects left open after offsets" << list(left_open);
  fs::remove_all(dir);
}

/// Replaces the values of a dataset through HDF5: a chunk that passes its
/// Fletcher32 but is not what the checkpoint's writer wrote (a chunk index
/// pointing at another dataset's chunk, or at none: HDF5 reads zeros).
void overwrite_dataset(const fs::path& path, const char* name, const std::vector<double>& values) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t set = H5Dopen2(file, name, H5P_DEFAULT);
  ASSERT_GE(set, 0);
  EXPECT_GE(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  H5Dclose(set);
  H5Fclose(file);
}

TEST(Checkpoint, RefusesADatasetThatPassesFletcher32ButIsNotWhatWasWritten) {
  const auto dir = fresh_directory("replaced_chunk");
  const fs::path path = dir / "checkpoint.h5";
  write_checkpoint(path, sample());
  overwrite_dataset(path, "/state/time_loop/solution", {0.0, 0.0, 0.0, 0.0});
  const std::string message = read_error(path);
  EXPECT_NE(message.find("corrupt checkpoint"), std::string::npos) << message;
  EXPECT_NE(message.find("state/time_loop/solution"), std::string::npos) << message;
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  fs::remove_all(dir);
}

// The reference implementation's values (xxhash 0.8's XXH64).
TEST(Xxh64, MatchesTheReferenceImplementation) {
  const std::string fox = "The quick brown fox jumps over the lazy dog";  // > 32 bytes: stripes
  EXPECT_EQ(xxh64("", 0), 0xEF46DB3751D8E999ULL);
  EXPECT_EQ(xxh64("abc", 3), 0x44BC2CF5AD770999ULL);
  EXPECT_EQ(xxh64(fox.data(), fox.size()), 0x0B242D361FDA71BCULL);
  EXPECT_EQ(xxh64(fox.data(), fox.size(), 42), 0xAA9F288A8BAA3D3FULL);
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
