// A module of the time step added in one file, with no edit to the driver
// (issue 30): a passive dye carried by the flow. It starts as c = y, the
// height of the undisturbed shear flow's streamline through each point, and
// is transported with the velocity in the ALE frame (physics::AleTransport,
// SUPG, BDF2) at stage advance_fields. Registered at run time
// (register_module_type), it must show up in every product of a run: its
// own report file (dye.csv), summary.json, the ParaView fields and the
// checkpoint, from which a restart continues it to round-off.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <mpi.h>

#include "softflow/fem/dof_map.hpp"
#include "softflow/fem/field.hpp"
#include "softflow/fem/space.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/io/checkpoint.hpp"
#include "softflow/physics/stokes/stokes_problem.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/physics/transport/ale_transport.hpp"
#include "softflow/simulation/drop_run.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/run_support.hpp"
#include "softflow/simulation/step_module.hpp"
#include "support/verification/restart_runs.hpp"

using namespace softflow;
namespace fs = std::filesystem;

namespace {

class PassiveDye final : public simulation::StepModule {
 public:
  explicit PassiveDye(const simulation::ModuleSetup& setup)
      : p1_(std::make_shared<fem::Space>(setup.mesh, 1, fem::Continuity::continuous)),
        p2_(std::make_shared<fem::Space>(setup.mesh, 2, fem::Continuity::continuous)),
        dye_(setup.mesh, "dye", p1_, 1),
        velocity_(setup.mesh, "dye_velocity", p2_, 3),
        mesh_velocity_(setup.mesh, "dye_mesh_velocity", p2_, 3) {
    std::vector<double> y(dye_.dofs().n_dofs());
    for (int node = 0; node < setup.mesh.n_nodes(); ++node)
      if (const int dof = dye_.dofs().dof(0, node, 0, 0); dof >= 0) y[dof] = setup.mesh.nodes[node].y();
    dye_.scatter(y);
    initial_ = y;
    transport_ = std::make_unique<physics::AleTransport>(dye_);
  }

  [[nodiscard]] std::string name() const override { return "dye"; }
  void restart_time_history() override { transport_->restart_history(); }
  void advance(const simulation::StepContext& context) override {
    velocity_.assign_from(context.stokes.dofs(), physics::kVelocityField, context.solution);
    std::vector<double> w(mesh_velocity_.dofs().n_dofs(), 0.0);
    for (int node = 0; node < context.mesh.n_nodes(); ++node)
      for (int c = 0; c < 3; ++c) w[mesh_velocity_.dofs().dof(0, node, 0, c)] = context.mesh_velocity[node](c);
    mesh_velocity_.scatter(w);
    transport_->step(velocity_, &mesh_velocity_, {}, context.dt, context.time);
  }
  void measure(const simulation::StepContext&, simulation::StepReport&) override {
    const auto all = dye_.gather();
    const auto [lo, hi] = std::minmax_element(all.begin(), all.end());
    min_ = *lo;
    max_ = *hi;
    change_ = 0.0;  // how far the flow has moved the dye from its streamline heights
    for (std::size_t i = 0; i < all.size(); ++i) change_ = std::max(change_, std::abs(all[i] - initial_[i]));
  }
  std::vector<fem::Field*> fields() override { return {&dye_}; }
  std::vector<StatePart> state_parts() override { return {transport_->state_part()}; }
  std::vector<simulation::ReportFile> report_files() const override {
    return {{"dye.csv", "step,t,dye_min,dye_max,dye_change\n", [this](const simulation::StepReport& r) {
               return fmt::format("{},{:.10g},{:.10g},{:.10g},{:.10g}\n", r.step, r.time, min_, max_,
                                  change_);
             }}};
  }
  void summarise(nlohmann::json& summary) const override {
    summary["final_dye"] = {{"min", min_}, {"max", max_}};
  }

 private:
  std::shared_ptr<const fem::Space> p1_, p2_;
  fem::Field dye_, velocity_, mesh_velocity_;
  std::unique_ptr<physics::AleTransport> transport_;
  std::vector<double> initial_;
  double min_ = 0.0, max_ = 0.0, change_ = 0.0;
};

// The one line a new module needs (here at run time, as a program of its own would).
const bool kRegistered = [] {
  simulation::register_module_type(
      {"dye", [](const simulation::ModuleSetup&) { return true; },
       [](const simulation::ModuleSetup& s) -> std::unique_ptr<simulation::StepModule> {
         return std::make_unique<PassiveDye>(s);
       }});
  return true;
}();

// A module that ends the run at t >= 0.1: the run completes there, says why,
// and a restart has nothing to do. Only for cases named "finishing".
class FinishAtTenth final : public simulation::StepModule {
 public:
  explicit FinishAtTenth(const simulation::ModuleSetup&) {}
  [[nodiscard]] std::string name() const override { return "finish_at_tenth"; }
  void measure(const simulation::StepContext& context, simulation::StepReport&) override {
    time_ = context.time;
  }
  [[nodiscard]] std::string finished() const override {
    return time_ >= 0.1 - 1e-12 ? fmt::format("reached t = {:.2f}, the test's end", time_) : "";
  }

 private:
  double time_ = 0.0;
};

const bool kFinisherRegistered = [] {
  simulation::register_module_type(
      {"finish_at_tenth", [](const simulation::ModuleSetup& s) { return s.config.name == "finishing"; },
       [](const simulation::ModuleSetup& s) -> std::unique_ptr<simulation::StepModule> {
         return std::make_unique<FinishAtTenth>(s);
       }});
  return true;
}();

io::CaseConfig small_case(const std::string& name, const fs::path& directory) {
  return io::parse_case(
      "[cell]\nlength = 8.0\nheight = 8.0\nwidth = 8.0\n"
      "[[objects]]\ncapillary_number = 0.1\n"
      "[mesh]\nequator_nodes = 16\nfar_size = 2.0\n"
      "[time]\nstep = 0.05\nend = 0.2\nfields_interval = 2\n"
      "[output]\nfields = true\ndirectory = \"" + directory.string() + "\"\n",
      name);
}

bool is_root() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank == 0;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST(StepModule, AppearsInReportSummaryFieldsAndCheckpoint) {
  ASSERT_TRUE(kRegistered);
  const fs::path directory = fs::temp_directory_path() / "softflow_step_module_run";
  fs::remove_all(directory);
  const auto config = small_case("dye_run", directory);
  simulation::RunOptions options;
  options.quiet = true;
  const auto summary = simulation::run_drop_case(config, options, simulation::build_mesh(config));
  if (!is_root()) return;

  // Its report file: the header, then steps 0..4, the dye's range within the
  // walls' heights (+-4) up to the transport's small overshoot.
  std::istringstream csv(read_text(directory / "dye.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "step,t,dye_min,dye_max,dye_change");
  int rows = 0;
  while (std::getline(csv, line)) {
    int step = -1;
    double t = 0.0, lo = 0.0, hi = 0.0, change = 0.0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%d,%lf,%lf,%lf,%lf", &step, &t, &lo, &hi, &change), 5)
        << line;
    EXPECT_EQ(step, rows);
    if (step == 0) {  // c = y at the nodes: the walls exactly
      EXPECT_DOUBLE_EQ(lo, -4.0);
      EXPECT_DOUBLE_EQ(hi, 4.0);
      EXPECT_EQ(change, 0.0);
    } else {  // the drop's disturbance carries the dye off its heights
      EXPECT_GT(change, 1e-3) << line;
    }
    EXPECT_GT(lo, -4.0 * 1.01) << line;
    EXPECT_LT(hi, 4.0 * 1.01) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 5);

  ASSERT_TRUE(summary.contains("final_dye"));
  EXPECT_LT(summary["final_dye"]["max"].get<double>(), 4.04);
  const auto written = nlohmann::json::parse(read_text(directory / "summary.json"));
  EXPECT_EQ(written["final_dye"], summary["final_dye"]);

  // The ParaView pieces carry the field by name.
  bool field_written = false;
  for (const auto& entry : fs::recursive_directory_iterator(directory / "fields"))
    if (entry.path().extension() == ".vtu" &&
        read_text(entry.path()).find("Name=\"dye\"") != std::string::npos)
      field_written = true;
  EXPECT_TRUE(field_written);

  // The checkpoint: the field's values and the transport's BDF history.
  const auto checkpoint = io::read_checkpoint(directory / simulation::kCheckpointFile);
  EXPECT_TRUE(checkpoint.state.contains("fields/dye/values"));
  EXPECT_TRUE(checkpoint.state.contains("transport/dye/previous"));
  fs::remove_all(directory);
}

TEST(StepModule, RestartsToRoundOff) {
  ASSERT_TRUE(kRegistered);
  auto config = small_case("dye_restart", fs::temp_directory_path() / "softflow_step_module_restart");
  config.write_fields = false;
  const auto runs = verification::run_and_restart(config, 2, 4, "dye_restart");
  const auto differences = verification::output_field_differences(*runs.uninterrupted, *runs.restarted);
  ASSERT_EQ(differences.size(), 2u);  // Stokes, then the dye
  EXPECT_LT(differences[1], 1e-12);
  EXPECT_LT(differences[0], 1e-10);
}

TEST(StepModule, EndsTheRunWithItsReason) {
  ASSERT_TRUE(kFinisherRegistered);
  const fs::path directory = fs::temp_directory_path() / "softflow_step_module_finish";
  fs::remove_all(directory);
  auto config = small_case("finishing", directory);
  config.write_fields = false;
  simulation::RunOptions options;
  options.quiet = true;
  const auto summary = simulation::run_drop_case(config, options, simulation::build_mesh(config));
  EXPECT_EQ(summary["status"], "completed");
  EXPECT_EQ(summary["steps"], 2);  // t = 0.1 after two steps of 0.05, not time.end = 0.2
  EXPECT_EQ(summary["stop_reason"], "reached t = 0.10, the test's end");
  // The checkpoint knows: a restart has nothing to do and returns the summary.
  const auto again = simulation::restart_drop_case(config, directory, options);
  EXPECT_EQ(again["steps"], 2);
  if (is_root()) fs::remove_all(directory);
}
