// Case files: TOML text -> validated CaseConfig, the resolved case back to TOML, the key
// reference, and the dimensionless groups of a case. The keys themselves are declared once, in
// case_keys.cpp.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "softflow/geometry/remesh.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/physics/stokes/wall_motion.hpp"
#include "softflow/physics/transport/ale_transport.hpp"
#include "softflow/physics/viscoelastic/conformation_prediction.hpp"
#include "softflow/mesh/mesh.hpp"
#include "softflow/physics/viscoelastic/constitutive.hpp"

namespace softflow::io {

/// [solver] type. `automatic` ("auto") picks direct up to
/// la::kDirectSolverLimit unknowns, iterative above.
enum class SolverType { automatic, direct, iterative };

/// [solver] initial_guess: where the iterative solver starts each step.
enum class InitialGuess { extrapolated, previous };

/// How the walls move in time (SPEC §1); physics::WallMotion has the formulas.
enum class FlowType { steady, start_up, cessation, oscillatory };

/// [flow] beyond the shear rate: the wall-speed history u_w(t).
struct FlowConfig {
  FlowType type = FlowType::steady;
  double stop_time = 0.0;         ///< cessation: the walls stop at t = stop_time
  double strain_amplitude = 0.0;  ///< oscillatory: gamma0
  double frequency = 0.0;         ///< oscillatory: omega, angular (rad per time unit)
  /// oscillatory: > 0 ends the run after this many periods (time.end is set
  /// from it, periods 2 pi / frequency); 0: time.end as given.
  double periods = 0.0;
};

/// [[objects]] initial_deformation: the shape a sphere's mesh is deformed
/// into before the first step.
enum class InitialDeformation { none, taylor };

/// One suspended object of the case file ([[objects]]).
struct ObjectConfig {
  geometry::ObjectSpec geometry;
  /// The constitutive model of the object ([[objects]] model): a Newtonian
  /// or viscoelastic drop, or an elastic particle (neo_hookean,
  /// kelvin_voigt). object_constitutive() makes the model itself.
  physics::viscoelastic::ConstitutiveModel model =
      physics::viscoelastic::ConstitutiveModel::newtonian;
  /// A non-Newtonian object's parameters in the case's units, as the file
  /// gives them (solvent_viscosity, polymer_viscosity or modulus,
  /// relaxation_time, mobility); an elastic particle's modulus is always
  /// set, from elastic_capillary_number if the file gives that. All unset
  /// for a Newtonian object (its viscosity is viscosity_ratio * eta_m).
  physics::viscoelastic::ConstitutiveValues parameters;
  /// lambda = eta_d / eta_m, always resolved: as given for a Newtonian
  /// object, with eta_d = mu + G lambda, the zero-shear viscosity (thesis
  /// eq. 2.9), for a viscoelastic drop, +infinity for an elastic particle.
  double viscosity_ratio = 1.0;
  /// Gamma, always resolved: from the file, or Gamma = eta_m gamma_dot R / Ca;
  /// 0 for an elastic particle (no interfacial tension, SPEC §1).
  double interfacial_tension = 0.0;
  /// The capillary number as the user gave it (or the default 0.1); empty
  /// when the file gives interfacial_tension instead, and for an elastic
  /// particle. Kept so that the resolved case says what the user asked for,
  /// not a rounded Gamma.
  std::optional<double> capillary_number;
  /// An elastic particle's Ca_e = eta_m gamma_dot / G as the user gave it
  /// (then parameters.modulus = eta_m gamma_dot / Ca_e); empty when the file
  /// gives the modulus, and for a liquid object.
  std::optional<double> elastic_capillary_number;
  /// alpha, the dimensionless Navier slip coefficient of the interface
  /// ([[objects]] slip; thesis eq. 2.18 with the sign of SPEC §9):
  ///   (I - nn)(u_m - u_d) = alpha (I - nn)(sigma_m . n),
  /// n the object's outward normal (into the matrix), u_m, sigma_m the
  /// matrix's velocity and stress, u_d the object's velocity; it dissipates
  /// (u_m - u_d).(sigma_m n) = alpha |(I - nn) sigma_m n|^2 >= 0. Made
  /// dimensionless through R / eta_m (thesis §2.1): the solver's dimensional
  /// coefficient is slip * R / eta_m (navier_slip_coefficient), R the
  /// object's equivalent-sphere radius mean_radius(geometry), eta_m the
  /// matrix's zero-shear viscosity. 0 = no slip (the default); finite and
  /// >= 0, and 0 for an elastic particle.
  double slip = 0.0;
  /// taylor: the sphere's mesh deformed into the steady ellipsoid of
  /// small-deformation theory before the first step (Newtonian drops in
  /// steady shear without slip); none: the sphere itself.
  InitialDeformation initial_deformation = InitialDeformation::none;
};

/// [time]: the time loop (thesis §2.3.3). end = 0 means one Stokes solve of
/// the initial state and no time stepping.
struct TimeConfig {
  double step = 0.005;          ///< dt, in the case's time unit (1/gamma_dot when gamma_dot = 1)
  double end = 0.0;             ///< t_end >= 0
  int fields_interval = 0;      ///< write fields every this many steps (0: at the end only)
  double min_quality = 0.02;    ///< stop with a diagnosis if an element's quality falls below
  /// Stop with a diagnosis once an object's volume differs from its initial
  /// volume by more than this fraction.
  double max_volume_drift = 0.01;
  /// Below this minimum element quality the mesh-motion operator is rebuilt
  /// on the current mesh (and again after each further 5 % drop), as the
  /// thesis's incremental ALE does every step; 0 = always the initial mesh.
  double ale_rebuild_quality = 0.2;
  /// Below this element quality the free nodes (vertices and edge nodes) of the elements below it
  /// are relocated to improve them (mesh::NodeRelocation), as part of the
  /// step's mesh motion; 0 = never. Unset in the file: 0.2, and 0 with
  /// mesh.point_symmetric_start, whose mirror symmetry the search breaks.
  double relocation_quality = 0.2;
  /// > 0: stop before `end` once every object's D, shape vector
  /// D (cos 2 theta, sin 2 theta) and centre velocity relative to the shear
  /// flow at the centre (in units gamma_dot R)
  /// have changed by at most this over the last steady_window
  /// (analysis::SteadyStateMonitor); `end` is then the latest time. 0 = off.
  double steady_tolerance = 0.0;
  double steady_window = 5.0;  ///< the time span steady_tolerance is measured over
  /// > 0: the run ends once an object's interface is closer to a wall than
  /// this many of its radii (MigrationModule::finished). 0 = never.
  double min_wall_gap = 0.0;
  /// > 0: adaptive steps (time::StepController). `step` is then the first
  /// step; each later one keeps the largest predictor-corrector distance of
  /// the interface nodes (relative to the object's radius) near this,
  /// rejecting and retrying steps above it. 0 = constant steps of `step`.
  double adaptive_tolerance = 0.0;
  double max_step = 0.0;    ///< adaptive steps: largest step (0: no bound but max_growth)
  double max_growth = 2.0;  ///< adaptive steps: largest ratio of a step to the one before
  /// Not a key: what chose the steps, "time.step", "time.adaptive_tolerance"
  /// or "default" (neither given: adaptive where available, constant
  /// otherwise; resolve_default_steps). Printed by a run and in summary.json.
  std::string steps_chosen_by = "default";
};

/// [checkpoint]: when a run in time saves its state (checkpoint.h5 in the
/// output directory). It also does so at the end, on SIGINT/SIGTERM/SIGUSR1
/// and before the wall-time limit.
struct CheckpointConfig {
  int interval_steps = 0;          ///< every this many steps (0: not by step count)
  double interval_minutes = 10.0;  ///< at most this long apart in wall time (0: not by time)
};

/// [bulk_stress]: the emulsion's bulk stress (thesis eq. 4.1) averaged over
/// a cube centred in the cell, each step (bulk_stress.csv).
struct BulkStressConfig {
  double box_side = 0.0;  ///< side of the centred cube (0: no bulk stress)
  /// Oscillatory flow: G', G'' are fitted over the last this many periods.
  double fit_periods = 2.0;
};

/// [conformation]: the numerics of the conformation (log c) transport of
/// every phase that has one (viscoelastic liquids, elastic particles).
struct ConformationConfig {
  /// The SUPG parameter's kind per phase: `automatic` = transient in the
  /// elastic solids, steady (the thesis's) in viscoelastic liquids.
  enum class SupgTau { automatic, transient, steady };
  SupgTau supg_tau = SupgTau::automatic;
  /// The conformation the Stokes step's polymer stress is taken at
  /// (physics::viscoelastic::StressPrediction).
  physics::viscoelastic::StressPrediction stress_prediction =
      physics::viscoelastic::StressPrediction::consistent;
  /// The DEVSS-G term in every phase with a conformation (thesis eqs. 2.34, 2.36).
  bool devss_g = true;
};

/// [emulsion]: many drops at random (thesis ch. 4; docs/emulsions.md): the
/// single [[objects]] entry is the template, copied at the centres random
/// sequential addition picks (geometry::random_sequential_addition).
struct EmulsionConfig {
  double volume_fraction = 0.0;  ///< of the drops in the packing region (0: no emulsion)
  int seed = 1;
  /// Smallest gap between drops and to the region's faces, in drop radii
  /// (0: one interface element, the mesher's smallest).
  double min_gap = 0.0;
  /// Side of the centred cube the drops fill (the "frame" layout); 0: the cell.
  double core_side = 0.0;
  /// Which drops fill the core cube: those wholly inside it, or those whose
  /// centres lie in it, crossing its faces (the thesis's frame layout,
  /// ch. 4: the drops of a whole-cell packing with centres outside removed).
  enum class CoreLayout { inside, centres };
  CoreLayout core_layout = CoreLayout::inside;
};

/// [remesh]: meshing the deformed domain again during a run (issue 31).
struct RemeshConfig {
  /// Remesh before a step once the worst element quality is below this
  /// (0: never). Must exceed time.min_quality, which stops the run.
  double quality = 0.0;
  /// Remesh before a step once this much time has passed since the last
  /// remesh (or the start; 0: never): a schedule, for runs whose elements
  /// stretch without a poor one (long migrations).
  double interval = 0.0;
  /// Remesh before a step once an object's gap to a wall or to another
  /// object is crossed by fewer elements than this (0: never); below
  /// mesh.gap_elements, the count a remesh restores.
  double gap_elements = 0.0;
  /// Each object's interface at a remesh: kept node for node, sampled afresh
  /// at the case's sizes, or afresh only where it no longer fits them.
  geometry::InterfaceRemeshing interfaces = geometry::InterfaceRemeshing::automatic;

  /// Any trigger set: the run may remesh.
  [[nodiscard]] bool enabled() const { return quality > 0.0 || interval > 0.0 || gap_elements > 0.0; }
};

/// [interface]: interface tracking (thesis §2.2.3, §2.3.2).
struct InterfaceConfig {
  /// k / gamma_dot of eq. 2.30 (thesis: 10); with gamma_dot = 0, k itself.
  double redistribution_factor = 10.0;
  double supg_beta = 0.5;  ///< beta of tau = beta h / (2 U_t); 0.5 for P2
  /// Tension taken at the end-of-step interface position (physics::SemiImplicitTension):
  /// lifts the capillary time-step limit; false = the thesis's explicit tension.
  bool semi_implicit_tension = true;
};

/// A validated case. Every field holds a usable value: defaults are filled in.
struct CaseConfig {
  std::string name;                             ///< [case] name; default: the file stem
  mesh::Box box{30.0, 30.0, 30.0, true, true};  ///< [cell]; height resolved from blockage_ratio if given
  /// [cell] blockage_ratio beta = 2R/H as the file gives it (thesis ch. 3),
  /// R = mean_radius of objects[1]; box.height = 2R / beta then. Empty when
  /// the file gives the height (or neither: the default height).
  std::optional<double> blockage_ratio;
  /// [matrix] model: Newtonian, Oldroyd-B, Giesekus or UCM.
  physics::viscoelastic::ConstitutiveModel matrix_model =
      physics::viscoelastic::ConstitutiveModel::newtonian;
  /// A viscoelastic matrix's parameters as the file gives them (all unset
  /// for a Newtonian matrix); matrix_constitutive() makes the model.
  physics::viscoelastic::ConstitutiveValues matrix_parameters;
  /// eta_m, always resolved: [matrix] viscosity, or for a viscoelastic
  /// matrix its zero-shear viscosity mu + G lambda (thesis eq. 2.9), the
  /// eta_m of Ca, Ca_e, lambda and p.
  double matrix_viscosity = 1.0;
  /// gamma_dot >= 0, the characteristic shear rate: [flow] shear_rate while
  /// the walls move (0: a static case, e.g. drop relaxation); for oscillatory
  /// flow the shear-rate amplitude strain_amplitude * frequency (not a key
  /// then). Ca, the time unit and the redistribution factor use it.
  double shear_rate = 1.0;
  FlowConfig flow;  ///< [flow] type and the keys of that type
  std::vector<ObjectConfig> objects;       ///< [[objects]], in file order (object k = objects[k-1])
  geometry::MeshSizing sizing;             ///< [mesh]
  SolverType solver = SolverType::automatic;  ///< [solver] type
  double rtol = 1e-8;                      ///< [solver] rtol (iterative solver)
  int max_iterations = 500;                ///< [solver] max_iterations (iterative solver)
  InitialGuess initial_guess = InitialGuess::extrapolated;  ///< [solver] initial_guess
  std::string petsc_options;               ///< [solver] petsc_options, passed to PETSc as is
  /// [output] directory; default "output/<name>". Relative paths are taken
  /// from the working directory, not from the case file's folder.
  std::string output_directory;
  bool write_fields = true;  ///< [output] fields: write VTU/PVD fields
  TimeConfig time;            ///< [time]
  InterfaceConfig interface;  ///< [interface]
  ConformationConfig conformation;  ///< [conformation]
  CheckpointConfig checkpoint;  ///< [checkpoint]
  BulkStressConfig bulk_stress;  ///< [bulk_stress]
  EmulsionConfig emulsion;       ///< [emulsion]
  RemeshConfig remesh;          ///< [remesh]

  /// The geometry the mesher needs (geometry::validate checks overlaps and walls).
  [[nodiscard]] geometry::ShearCellSpec shear_cell_spec() const;
  /// u_w = gamma_dot H / 2: the walls y = +-H/2 move with (+-u_w, 0, 0)
  /// (the largest wall speed for start-up, cessation and oscillatory flow).
  [[nodiscard]] double wall_velocity() const { return shear_rate * box.height / 2.0; }
};

/// Ca = eta_m gamma_dot R / Gamma of `object` (one of config.objects), with
/// gamma_dot the case's characteristic shear rate (CaseConfig::shear_rate):
/// the value the file gave, else computed from Gamma; +inf when Gamma = 0.
/// Everything that needs an object's Ca (summary, theory, sweeps) asks here.
[[nodiscard]] double capillary_number(const CaseConfig& config, const ObjectConfig& object);

/// R = (abc)^(1/3): the radius of the sphere of equal volume, the length
/// scale of every dimensionless group of an object.
[[nodiscard]] double mean_radius(const geometry::ObjectSpec& object);

/// The dimensional Navier slip coefficient of `object`'s interface,
/// object.slip * R / eta_m (R = mean_radius, eta_m the matrix's zero-shear
/// viscosity), in the case's units: the alpha of
/// (I - nn)(u_m - u_d) = alpha (I - nn)(sigma_m . n). 0 without slip.
[[nodiscard]] double navier_slip_coefficient(const CaseConfig& config, const ObjectConfig& object);

/// True for the models of an elastic particle (neo_hookean, kelvin_voigt):
/// a solid, without interfacial tension.
[[nodiscard]] bool is_elastic_solid(physics::viscoelastic::ConstitutiveModel model);

/// Ca_e = eta_m gamma_dot / G of an elastic particle: as the file gave it,
/// else computed from the modulus; empty for a liquid object.
[[nodiscard]] std::optional<double> elastic_capillary_number(const CaseConfig& config,
                                                             const ObjectConfig& object);

/// The matrix's constitutive model: Constitutive::newtonian(eta_m) or the
/// viscoelastic model of [matrix].
[[nodiscard]] physics::viscoelastic::Constitutive matrix_constitutive(const CaseConfig& config);

/// The constitutive model of `object` (one of config.objects): for a
/// Newtonian object Constitutive::newtonian(viscosity_ratio * eta_m), with
/// eta_m the matrix's (zero-shear) viscosity.
[[nodiscard]] physics::viscoelastic::Constitutive object_constitutive(const CaseConfig& config,
                                                                      const ObjectConfig& object);

/// The constitutive model of every region: [0] the matrix, [k] object k
/// (config.objects[k-1]), in absolute units of the case.
[[nodiscard]] std::vector<physics::viscoelastic::Constitutive> constitutive_models(
    const CaseConfig& config);

/// The walls' motion the case asks for ([flow] type and its keys), built
/// here beside the rest of the flow's resolution (the shear rate of an
/// oscillatory flow, its dimensionless groups): a new wall motion touches
/// physics/stokes/wall_motion, the keys and this file.
[[nodiscard]] physics::WallMotion wall_motion(const CaseConfig& config);

/// Reads and validates a case file. Throws InputError with one line per
/// problem found ("case.toml: objects[2].radius = -1: must be > 0").
CaseConfig read_case_file(const std::filesystem::path& path);

/// The same from text; `source_name` is used in messages and its stem is the
/// default case name.
CaseConfig parse_case(const std::string& toml_text, const std::string& source_name);

/// Throws InputError when arrays or inline tables in `text` nest more than
/// 64 deep (toml11 parses them recursively: deeper input could overflow the
/// stack). Every reader of TOML text calls this before toml::parse.
void check_toml_nesting(std::string_view text, const std::string& source);

/// The longest directory name softflow can make: NAME_MAX (255 bytes on
/// Linux file systems) less the longest suffix it appends to a run's
/// directory, ".partial-<pid>" (16 bytes with a 7-digit pid: Linux pids stay
/// below 2^22 = 4194304). Its siblings ".old-<pid>" and ".lock" are shorter.
inline constexpr std::size_t kMaxDirectoryNameBytes = 255 - 16;
/// The longest output directory path: PATH_MAX (4096 bytes) less room for
/// the staging suffix and the longest name written in it (a sweep's
/// cases/<label>.toml.tmp-<pid>).
inline constexpr std::size_t kMaxDirectoryPathBytes = 3800;

/// "" or why `directory` cannot be a run's output directory, as a phrase to
/// follow "<key> = <value>: ": its last component longer than
/// kMaxDirectoryNameBytes, another longer than 255 bytes, or the whole path
/// longer than kMaxDirectoryPathBytes. (Such a run got as far as its first
/// mkdir and blamed a "stale directory ... File name too long".)
std::string output_directory_problem(const std::string& directory);

/// The words of a PETSc options string as PetscOptionsInsertString splits
/// it: at runs of spaces; a word that begins with '"' runs to the next '"'.
std::vector<std::string> petsc_option_words(std::string_view options);

/// Whether PETSc reads `word` as an option name (PetscOptionsValidKey): '-'
/// or "--" and a letter, and not a number ("-inf"); "-1" is a value.
bool is_petsc_option_name(std::string_view word);

/// "" or what is wrong with a list of PETSc option words (from
/// solver.petsc_options or after "--"): PETSc takes a word that is no option
/// name as the value of the option right before it, and skips any other
/// silently. Such a word ("ksp_monitor" without its dash, or "restart" in
/// "-ksp_type gmres restart") is named, with where it stands.
std::string petsc_words_problem(const std::vector<std::string>& words);

/// The resolved case as TOML: every key that applies, defaults filled in.
/// Reading it back gives the same CaseConfig, bit for bit.
std::string to_toml(const CaseConfig& config);

/// The reference of every case-file key as Markdown (docs/case_file_keys.md;
/// `softflow keys` prints it): generated from the declarations.
std::string case_file_keys_markdown();

/// One dimensionless number of a run, as reported in the summary.
struct DimensionlessGroup {
  std::string symbol;      ///< short ASCII symbol, e.g. "Ca", "lambda"
  std::string name;        ///< e.g. "capillary number"
  double value = 0.0;      ///< may be +inf (e.g. Ca without interfacial tension)
  std::string definition;  ///< e.g. "eta_m gamma_dot R / Gamma"
  int object = 0;          ///< object it belongs to (1-based); 0 = the whole case
};

/// Whether a phase carries a conformation (a viscoelastic matrix or object,
/// or an elastic particle's Finger tensor): its time error is one the
/// adaptive steps' interface estimate does not see.
[[nodiscard]] bool carries_conformation(const CaseConfig& c);

/// The transport's SUPG parameter in every region ([0] the matrix, [k]
/// object k) as [conformation] supg_tau resolves it.
[[nodiscard]] std::vector<physics::SupgTau> conformation_supg_taus(const CaseConfig& c);

/// Whether a phase is a viscoelastic liquid (a finite relaxation time: the
/// matrix or a drop of Oldroyd-B, Giesekus, UCM or FENE-P).
[[nodiscard]] bool has_relaxing_phase(const CaseConfig& c);

/// Whether any object has Navier slip: the Stokes system then has a
/// velocity copy per region coupled by multipliers (physics::StokesSystem),
/// which live on the interface nodes.
[[nodiscard]] bool has_interface_slip(const CaseConfig& c);

/// The groups of a case (SPEC §1), case-wide ones first (gamma0; a
/// viscoelastic matrix's Weissenberg number, and Deborah number in
/// oscillatory flow), then per object: for a drop Ca, omega*, lambda, p
/// (viscoelastic matrix), p_d and Wi_d (viscoelastic drop); for an elastic
/// particle Ca_e, p (viscoelastic matrix) and mu_d/eta_m (Kelvin-Voigt);
/// the slip alpha of an interface with slip > 0; for every object the
/// blockage beta = 2R/H and the box size in diameters L/2R, H/2R, W/2R.
std::vector<DimensionlessGroup> dimensionless_groups(const CaseConfig& config);

/// [{"symbol", "name", "object" (omitted for case-wide groups), "value"
/// (null when infinite), "definition"}, ...]
nlohmann::json to_json(const std::vector<DimensionlessGroup>& groups);

}  // namespace softflow::io
