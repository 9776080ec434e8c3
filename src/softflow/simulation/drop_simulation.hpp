// The ALE time loop for drops in shear: thesis §2.3.3, Steps 1-5, each a named stage.
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "softflow/common/state.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/io/checkpoint.hpp"
#include "softflow/io/vtu_writer.hpp"
#include "softflow/la/vector_values.hpp"
#include "softflow/mesh/mesh.hpp"
#include "softflow/physics/interface/interface_tracker.hpp"
#include "softflow/physics/stokes/interface_slip.hpp"
#include "softflow/physics/stokes/stokes_problem.hpp"
#include "softflow/simulation/object_interfaces.hpp"
#include "softflow/simulation/step_module.hpp"
#include "softflow/simulation/viscoelastic_phases.hpp"

namespace softflow::fem {
class Field;
}  // namespace softflow::fem

namespace softflow::physics {
class StokesSystem;
class MovingMesh;
}  // namespace softflow::physics

namespace softflow::simulation {

/// Wall time of each stage of one step, for finding what limits speed.
struct StageSeconds {
  double predict_and_translate = 0.0;  ///< Steps 1-2
  double ale = 0.0;                    ///< Step 3, with the quality check
  double stokes_assembly = 0.0;        ///< Step 4
  double stokes_solve = 0.0;           ///< Step 4
  double conformation = 0.0;           ///< stage advance_fields: the modules' (log-conformation transport, c, tau, G)
  double correct = 0.0;                ///< Step 5 (redistribution potential included)
  double analysis = 0.0;               ///< stage measure: ellipsoid fit, volume, area, the modules' measures
};

/// One remesh of a run (DropSimulation::remesh): remesh.csv's row.
struct RemeshEvent {
  int step = 0;       ///< after this step
  double time = 0.0;
  std::string reason;
  int nodes_before = 0, nodes_after = 0;
  double quality_before = 0.0, quality_after = 0.0;
  /// The worst interface triangle's shape (mesh::min_interface_shape): the
  /// interfaces are kept as they are, so it bounds the new mesh's elements there.
  double interface_shape = 1.0;
  std::string algorithm;  ///< gmsh's 3D algorithm of the mesh kept: "delaunay" or "hxt"
  /// Interface triangles of all objects before and after, and how many
  /// objects' interfaces were sampled afresh (remesh.interfaces).
  int interface_triangles_before = 0, interface_triangles_after = 0;
  int resampled = 0;
  /// Largest relative change of an object's enclosed volume (round-off: a
  /// kept interface is carried over node for node, a resampled one has its
  /// volume restored).
  double volume_change = 0.0;
  /// How far the transfer extrapolated (reference coordinates; ~0).
  double extrapolation = 0.0;
  double seconds = 0.0;
};

struct StepReport {
  int step = 0;
  StageSeconds stages;
  double time = 0.0;
  double min_quality = 0.0;
  int stokes_iterations = 0;
  double step_seconds = 0.0;
  /// The step's size t_{n+1} - t_n.
  double dt = 0.0;
  /// The step's error estimate: over every object and interface node, the
  /// largest distance between the predicted (eq. 2.49) and the corrected
  /// (eq. 2.50) position, relative to the object's radius. NaN at a BDF1
  /// step, whose predictor does not extrapolate (eq. 2.47).
  double interface_change = std::numeric_limits<double>::quiet_NaN();
  std::vector<ObjectState> objects;
  /// The mean polymer/elastic stress of every region with a conformation
  /// tensor (none for Newtonian runs; ViscoelasticModule).
  std::vector<RegionStress> stresses;
  /// Per object, the slip across its interface (runs with slip only; SlipModule).
  std::vector<physics::SlipMeasures> slips;
};

/// One time step from t_n to t_{n+1} = t_n + dt:
///   1. predict_interfaces   x_hat_{n+1} = 2 x_n - x_{n-1} (eq. 2.49; x_n at the first step)
///   2. translate_mesh       d1 = (X_x,n+1 - X_x,n, 0, 0) with X the centre of volume
///   3. move_mesh_ale        grad.(k_e grad d2) = 0, d2 = interface motion on S, 0 outside (eq. 2.55);
///                           mesh velocity u_m by BDF1, then BDF2
///   4. solve_stokes         u_{n+1}, p_{n+1} on the moved mesh (eqs. 2.34-2.35), the
///                           tension optionally semi-implicit (physics::SemiImplicitTension)
///   5. correct_interfaces   x_{n+1} from the SUPG surface convection equation (eq. 2.50)
/// The ALE operator lives on the reference (initial) mesh and is factored
/// once; the total displacement from the reference mesh is solved for, which
/// for a constant linear operator equals the sum of the thesis's increments.
class DropSimulation {
 public:
  DropSimulation(const io::CaseConfig& config, mesh::Mesh mesh);
  ~DropSimulation();

  /// The state at t = 0 (after no step).
  [[nodiscard]] StepReport initial_report();
  /// The current state (no stage timings, no solver iterations): after a
  /// restart, what the last step reported.
  [[nodiscard]] StepReport current_report();
  /// Advances one step of size dt (time.step if not given; it may change
  /// from step to step, every BDF2 then takes its variable-step form) and
  /// reports the new state. Stops the run with a diagnosis (step, time,
  /// where, what to try) on a degraded mesh (MeshError) or a failed or
  /// non-finite Stokes solution (SolverError); the state is then partly
  /// advanced: restore_step_state() takes it back.
  StepReport step(double dt);
  StepReport step() { return step(config_.time.step); }
  /// The state the next step starts from, in memory: every registered part
  /// but the Stokes solver's factorisation (any factors precondition the
  /// next solve). For retrying a step at another size.
  [[nodiscard]] StateRecord save_step_state() const;
  void restore_step_state(const StateRecord& state);
  /// Meshes the current domain again (geometry::remesh: the interfaces
  /// node for node, the box and sizes of the case) and carries the run
  /// over to the new mesh, which becomes the reference mesh of later
  /// checkpoints: the Stokes solution and every module field by
  /// fem::MeshTransfer (region by region), a kept interface's tracker
  /// history as it is (the same interface nodes, the same reference areas of
  /// eq. 2.32), a resampled interface's tracker afresh (BDF1 at the next
  /// step, its new triangles' areas as the reference: remesh.interfaces),
  /// the moving mesh fresh on the new mesh (mesh velocity BDF1 at the next
  /// step), the modules' multistep histories restarted at BDF1 (as after a
  /// jump of the walls); a restart from a checkpoint written after it
  /// continues alike. Fields added with add_field
  /// from outside a module are not carried (Error if there are any).
  /// Collective: rank 0 meshes, every rank receives the mesh. Throws
  /// MeshError, with the run unchanged, when gmsh cannot make a valid mesh.
  RemeshEvent remesh(const std::string& reason);

  /// Throws AccuracyError (with step, object, drift and what to try) if an
  /// object's volume has drifted past time.max_volume_drift. Separate from
  /// step(), so that the offending step is recorded before the run stops.
  void check_volumes() const;

  /// Fills the simulation's part of a checkpoint: the reference mesh and
  /// the state of every registered part (registry()).
  void save(io::Checkpoint& checkpoint) const;
  /// Continues from a checkpoint written by save() for the same case and
  /// reference mesh (the one this simulation was constructed with).
  void restore(const io::Checkpoint& checkpoint);
  /// The parts whose state a checkpoint carries: "time_loop" (time, mesh,
  /// mesh velocity, solution, ALE reference), "stokes" (the solver's
  /// factorisation reuse), "objects/<k>" (interface histories), then each
  /// module's fields and state parts. Extra fields and histories register
  /// here (e.g. fem::state_part of a Field) and are checkpointed and
  /// restored with no further code.
  [[nodiscard]] StateRegistry& registry() { return registry_; }
  /// Adds a field to the run: registered for checkpoints (fem::state_part)
  /// and written with the ParaView output. The field must outlive the
  /// simulation and live on its mesh (mesh()); its evolution is the
  /// caller's (e.g. a transport step after each step()).
  void add_field(fem::Field& field);
  /// The fields the ParaView output writes: the Stokes solution (velocity,
  /// pressure), then every added field, gathered. Collective.
  [[nodiscard]] std::vector<io::FieldData> output_fields() const;

  [[nodiscard]] const mesh::Mesh& mesh() const { return mesh_; }
  [[nodiscard]] const physics::StokesSystem& stokes() const { return *stokes_; }
  /// The last Stokes solution as solved: this rank's rows (null before the first step).
  [[nodiscard]] Vec distributed_solution() const { return solution_.get(); }
  /// The same, every dof on every rank (empty before the first step).
  /// Collective; for analysis and tests: no stage of a step needs it.
  [[nodiscard]] std::vector<double> solution() const;
  /// u_m at every geometry node over the last step (BDF1, then BDF2; zero before any step).
  [[nodiscard]] const std::vector<mesh::Point>& mesh_velocity() const;
  [[nodiscard]] double time() const { return time_; }
  /// The smallest element quality of the current mesh.
  [[nodiscard]] double mesh_quality() const;
  /// How often the mesh-motion operator was rebuilt on the current mesh.
  [[nodiscard]] int ale_rebuilds() const;
  /// Steps whose mesh motion relocated vertices (time.relocation_quality),
  /// and the node moves over all of them (a node moved in two steps counts twice).
  [[nodiscard]] int relocation_steps() const;
  [[nodiscard]] int relocated_nodes() const;
  [[nodiscard]] int steps() const { return steps_; }
  /// Each object's volume at t = 0 (the reference for the volume drift).
  [[nodiscard]] const std::vector<double>& initial_volumes() const { return interfaces_->initial_volumes(); }
  /// The viscoelastic phases (nullptr if every phase is Newtonian).
  [[nodiscard]] const ViscoelasticPhases* viscoelastic() const;
  /// The run's modules (step_module.hpp), in the order they are stepped.
  [[nodiscard]] const std::vector<std::unique_ptr<StepModule>>& modules() const { return modules_; }
  /// The per-step report files: timeseries.csv, then every module's.
  [[nodiscard]] std::vector<ReportFile> report_files() const;
  /// Adds every module's final values to summary.json.
  void summarise(nlohmann::json& summary) const;
  /// The first module's reason to end the run now (StepModule::finished), or "".
  [[nodiscard]] std::string finish_reason() const;
  /// Whether the run has interface slip (slip.csv, both velocity copies in the fields).
  [[nodiscard]] bool interface_slip() const;

 private:
  /// Step 2: the centres' velocities; the mesh follows a single object along x.
  std::vector<physics::Vec3> translate_mesh(const InterfacePositions& x_hat, double dt);
  /// BDF1 again for every history (interfaces, mesh velocity, conformation)
  /// after a jump in the wall speed.
  void restart_time_histories();
  /// Step 3 (physics::MovingMesh), then the quality check: MeshError below time.min_quality.
  double move_mesh_ale(const InterfacePositions& x_hat, double dt);
  int solve_stokes(const InterfacePositions& x_hat, double dt,
                   StageSeconds& stages);
  /// The fluid velocity of the last solve at interface node `node` of
  /// object `object` (1-based).
  [[nodiscard]] physics::Vec3 interface_velocity(int node, int object) const;
  /// interface_velocity for the interfaces' stages.
  [[nodiscard]] InterfaceVelocity fluid_at_interface() const;
  /// What the modules see of the run: `step` is the step being taken (or the current one).
  [[nodiscard]] StepContext context(double dt, int step) const;
  /// Stage measure for every object and module: the state in `r`.
  void measure_all(StepReport& r, const std::vector<physics::Vec3>& centre_velocity, double dt,
                   int step);
  void check_solution_finite() const;
  /// The global Stokes dofs the interface stages read (interface_values_):
  /// both velocity copies, and with slip the multipliers, of every interface node.
  [[nodiscard]] std::vector<PetscInt> interface_dofs() const;
  /// Takes `solution` as the current one and copies its interface dofs here. Collective.
  void set_solution(la::Vector solution);
  void register_state();
  /// The Stokes system, moving mesh, trackers and modules on mesh_ (constructor, remesh).
  void build_parts();
  void save_time_loop(StateRecord& record, const std::string& prefix) const;
  void restore_time_loop(const StateRecord& record, const std::string& prefix);

  io::CaseConfig config_;
  // Each region's constitutive model, built once from config_ (0 = matrix).
  std::vector<physics::viscoelastic::Constitutive> models_;
  mesh::Mesh mesh_;
  std::vector<mesh::Point> initial_nodes_;    // the mesh as meshed: what a restart starts from
  std::unique_ptr<physics::StokesSystem> stokes_;
  std::unique_ptr<physics::MovingMesh> moving_mesh_;
  std::unique_ptr<ObjectInterfaces> interfaces_;
  std::vector<std::unique_ptr<StepModule>> modules_;
  // The Stokes solution stays distributed; the trackers, the semi-implicit
  // tension and the slip measures read the interface dofs, copied to every
  // rank after each solve (interface_values_).
  la::Vector solution_;
  la::SelectedEntries interface_values_;
  double time_ = 0.0;
  int steps_ = 0;
  StateRegistry registry_;
  std::vector<fem::Field*> added_fields_;
};


}  // namespace softflow::simulation
