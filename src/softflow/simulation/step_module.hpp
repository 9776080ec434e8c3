// The time step's plug-in modules: physics, measurements and outputs that join a
// run by implementing the hooks of the step's named stages (issue 30).
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <petscvec.h>

#include "softflow/common/state.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/la/vector_values.hpp"
#include "softflow/mesh/mesh.hpp"
#include "softflow/physics/interface/interface_tracker.hpp"
#include "softflow/physics/viscoelastic/constitutive.hpp"

namespace softflow::fem {
class Field;
class MeshTransfer;
}  // namespace softflow::fem

namespace softflow::physics {
class StokesSystem;
struct StokesProblem;
}  // namespace softflow::physics

namespace softflow::simulation {

struct StepReport;

/// The named stages of one time step (thesis §2.3.3), in order. The driver
/// (DropSimulation::step) runs its own part of each stage, then every
/// module's hook for it:
///   restart_histories   only after a jump of the wall speed: BDF1 again
///   predict_interfaces  x_hat = 2 x_n - x_{n-1} (eq. 2.49)
///   move_mesh           translation and ALE motion (eq. 2.55), mesh velocity
///   solve_flow          StepModule::contribute, then the Stokes solve (eqs. 2.34-2.35)
///   advance_fields      StepModule::advance: fields carried by the new flow
///   correct_interfaces  x_{n+1} (eq. 2.50)
///   measure             StepModule::measure: the step's quantities and checks
///   output              StepModule::report_files rows, fields, summary (drop_run)
enum class Stage {
  restart_histories,
  predict_interfaces,
  move_mesh,
  solve_flow,
  advance_fields,
  correct_interfaces,
  measure,
  output
};

/// What a module may read of the run at a stage. `solution` and
/// `interface_values` are the last Stokes solution (null before the
/// first solve); `time` is t_{n+1} from solve_flow on, `step` the number of
/// the step being taken (the current step outside step()).
struct StepContext {
  const io::CaseConfig& config;
  const mesh::Mesh& mesh;
  const physics::StokesSystem& stokes;
  Vec solution = nullptr;
  /// The Stokes dofs of every interface node (both velocity copies, slip
  /// multipliers), on every rank; indexed by global dof.
  const la::SelectedEntries* interface_values = nullptr;
  std::span<const mesh::Point> mesh_velocity = {};
  /// Every object's interface (1-based object k is interfaces[k - 1]): at
  /// stage measure its corrected positions x_{n+1}, while the mesh's
  /// interface nodes are still at the predicted x_hat the flow was solved on.
  std::span<const physics::InterfaceTracker> interfaces = {};
  double time = 0.0;
  double dt = 0.0;
  int step = 0;
};

/// A per-step report file of a module (e.g. stress.csv): its header, and the
/// rows of the state last measured, one call per step.
struct ReportFile {
  std::string name;
  std::string header;
  std::function<std::string(const StepReport&)> rows;
};

/// A module of the time step. Every hook is optional; a module that only
/// measures implements measure() and report_files(). Its state is saved and
/// restored by itself (state_parts()), its fields written for ParaView and
/// checkpointed with no code in the driver or the run loop.
class StepModule {
 public:
  virtual ~StepModule() = default;
  /// Unique among a run's modules; names the module in messages.
  [[nodiscard]] virtual std::string name() const = 0;

  /// Stage restart_histories: multistep histories start again at BDF1.
  virtual void restart_time_history() {}
  /// Stage solve_flow, before the solve: this module's terms of the Stokes
  /// problem of the step (context.time is t_{n+1}). Collective.
  virtual void contribute(physics::StokesProblem& /*problem*/, const StepContext& /*context*/) {}
  /// Stage advance_fields: after the Stokes solve, fields carried by the new
  /// flow to t_{n+1}. Collective.
  virtual void advance(const StepContext& /*context*/) {}
  /// Stage measure: this module's quantities of the state in `context`
  /// (also at t = 0 and after a restart, with no step taken); may add to
  /// `report`, and throws AccuracyError when they show the step is wrong.
  /// Collective.
  virtual void measure(const StepContext& /*context*/, StepReport& /*report*/) {}

  /// After a remesh (DropSimulation::remesh): this module, built afresh on
  /// the new mesh, takes over the state of `old`, the same kind of module
  /// on the old mesh (only its fields' values may be read: its mesh is
  /// gone), through `transfer`. The default carries every fields() value
  /// over and restarts the multistep histories (restart_time_history).
  /// Collective.
  virtual void carry_over(StepModule& old, const fem::MeshTransfer& transfer);

  /// Fields written with the ParaView output and saved in checkpoints.
  [[nodiscard]] virtual std::vector<fem::Field*> fields() { return {}; }
  /// Other state a checkpoint needs (histories, counters); names unique.
  [[nodiscard]] virtual std::vector<StatePart> state_parts() { return {}; }
  /// The module's per-step report files.
  [[nodiscard]] virtual std::vector<ReportFile> report_files() const { return {}; }
  /// Adds the module's final values to summary.json.
  virtual void summarise(nlohmann::json& /*summary*/) const {}
  /// After measure: why the run is finished now (e.g. a particle reached a
  /// neutral height or came too close to a wall), or "" to go on. The run
  /// then ends as completed, with the reason in summary.json.
  [[nodiscard]] virtual std::string finished() const { return {}; }
};

/// Sets each field of `to` from the field of `from` with its name (old
/// mesh), through `transfer`. Collective.
void carry_fields_over(std::span<fem::Field* const> to, std::span<fem::Field* const> from,
                       const fem::MeshTransfer& transfer);

/// What a module is built from: the case, the run's mesh (which outlives the
/// module), its Stokes system and its constitutive models.
struct ModuleSetup {
  const io::CaseConfig& config;
  const mesh::Mesh& mesh;
  const physics::StokesSystem& stokes;
  /// The constitutive model of every region ([0] the matrix, [k] object k),
  /// built once per run (phase_models).
  std::span<const physics::viscoelastic::Constitutive> models;
};

/// A kind of module: whether a case needs it, how to build it, and its
/// report files' column reference (docs/output_columns.md).
struct ModuleType {
  std::string name;
  std::function<bool(const ModuleSetup&)> wanted;
  std::function<std::unique_ptr<StepModule>(const ModuleSetup&)> make;
  std::function<std::string()> columns_markdown = [] { return std::string(); };
};

/// Every known module type, in the order a run builds and steps them: the
/// built-in ones (simulation/modules/registry.cpp), then any registered.
const std::vector<ModuleType>& module_types();
/// Adds a module type for the rest of the process (e.g. a test's, or a
/// program's own); its name must be new.
void register_module_type(ModuleType type);
/// The modules `setup.config` wants, in module_types() order.
std::vector<std::unique_ptr<StepModule>> make_modules(const ModuleSetup& setup);

}  // namespace softflow::simulation
