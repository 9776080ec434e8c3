#include "softflow/io/case_keys.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>

#include <fmt/format.h>

namespace softflow::io {

namespace {

using namespace schema;  // NOLINT: the declarations below read as a table with it

bool is_control(char ch) {
  const auto c = static_cast<unsigned char>(ch);
  return c < 0x20 || c == 0x7f;
}

/// "" or what is wrong: a name or path with a control character (a newline,
/// a bell) would make file names that cannot be typed or listed sensibly.
std::string control_character_problem(const std::string& s) {
  const auto it = std::find_if(s.begin(), s.end(), is_control);
  if (it == s.end()) return "";
  return fmt::format("must not contain control characters (found U+{:04X} at position {}); "
                     "use printable characters only",
                     static_cast<unsigned>(static_cast<unsigned char>(*it)),
                     it - s.begin() + 1);
}

/// "" or what is wrong with a case name (the key's own rule; whether it
/// fits a directory name depends on output.directory and is checked with
/// it, in case_config.cpp).
std::string case_name_problem(const std::string& s) {
  if (auto what = control_character_problem(s); !what.empty()) return what;
  if (!s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c == ' '; }))
    return "must contain a character other than spaces (it names the run and its output "
           "directory)";
  return is_plain_name(s) ? ""
                          : "must be a non-empty name without '/' or '\\' (it names the output "
                            "directory)";
}

/// "" or what is wrong with solver.petsc_options: a word PETSc would skip
/// without a word (petsc_words_problem), or a tab or line break, at which
/// PETSc does not split ("-a\t1" would be one option named "a\t1").
std::string petsc_options_problem(const std::string& s) {
  const auto it = std::find_if(s.begin(), s.end(), is_control);
  if (it != s.end())
    return fmt::format("must not contain control characters (found U+{:04X} at position {}): "
                       "PETSc separates options at spaces only, so separate them with spaces",
                       static_cast<unsigned>(static_cast<unsigned char>(*it)),
                       it - s.begin() + 1);
  return petsc_words_problem(petsc_option_words(s));
}

// ---- the tables that fill CaseConfig itself ----

Table<CaseConfig> case_table() {
  return {"case", "What the run is called.", false,
          {text("name", field(&CaseConfig::name), Computed{"the case file's name without .toml"},
                fmt::format("names the run and, unless output.directory is given, its output "
                            "directory `output/<name>`: then at most {} bytes (a directory "
                            "name's 255 less the 16 of the suffix `.partial-<pid>` a run is "
                            "staged under); not only spaces",
                            kMaxDirectoryNameBytes),
                case_name_problem)}};
}

Table<CaseConfig> cell_table() {
  const auto box = [](auto member) { return field(&CaseConfig::box, member); };
  return {"cell",
          "The box [-L/2, L/2] x [-H/2, H/2] x [-W/2, W/2] between the moving walls y = +-H/2.",
          false,
          {number("length", box(&mesh::Box::length), 30.0, Range::above(0),
                  "L along x, the flow direction"),
           number("height", box(&mesh::Box::height), 30.0, Range::above(0),
                  "H along y, the velocity gradient; the walls are at y = +-H/2. Give this or "
                  "blockage_ratio, not both")
               // Written only when it was not computed from blockage_ratio.
               .printed_if([](const CaseConfig& c) { return !c.blockage_ratio; }),
           optional_number("blockage_ratio", field(&CaseConfig::blockage_ratio),
                           Computed{"2R / height"}, Range::open(0, 1),
                           "beta = 2R / H, the confinement of thesis ch. 3: sets the height "
                           "H = 2R / beta, R = (abc)^(1/3) the equivalent radius of objects[1] "
                           "(needs an [[objects]] entry). Give this or height, not both; an "
                           "off-centre start y_p0 (in units of H, as the thesis) is objects[1]."
                           "centre = [0, y_p0 H, 0]")
               .with_comment([](const CaseConfig& c) {
                 return fmt::format("height H = 2R / blockage_ratio = {}",
                                    toml_float(c.box.height));
               }),
           number("width", box(&mesh::Box::width), 30.0, Range::above(0),
                  "W along z, the vorticity direction"),
           boolean("periodic_x", box(&mesh::Box::periodic_x), true,
                   "periodic in x; false puts the undisturbed shear flow on the x faces"),
           boolean("periodic_z", box(&mesh::Box::periodic_z), true,
                   "periodic in z; false puts the undisturbed shear flow on the z faces")}};
}

// ---- constitutive models (thesis §2.2.1-2.2.2; SPEC §1) ----

using physics::viscoelastic::ConstitutiveModel;
using physics::viscoelastic::ConstitutiveValues;

const std::vector<std::string> kLiquids{"newtonian", "oldroyd_b", "giesekus", "ucm", "fene_p"};
const std::vector<std::string> kViscoelasticLiquids{"oldroyd_b", "giesekus", "ucm", "fene_p"};

/// The words of `model`: the liquids, and for objects also the elastic solids.
std::vector<Option<ConstitutiveModel>> model_options(bool solids) {
  std::vector<Option<ConstitutiveModel>> options{
      {"newtonian", ConstitutiveModel::newtonian, "T = 2 eta D (eq. 2.4)"},
      {"oldroyd_b", ConstitutiveModel::oldroyd_b,
       "T = 2 mu D + G (c - I) with lambda c_UC + (c - I) = 0 (eqs. 2.5-2.7, alpha = 0)"},
      {"giesekus", ConstitutiveModel::giesekus,
       "T = 2 mu D + G (c - I) with lambda c_UC + (c - I) + alpha (c - I)^2 = 0 (eqs. 2.5-2.7)"},
      {"ucm", ConstitutiveModel::ucm, "Oldroyd-B without solvent (mu = 0)"},
      {"fene_p", ConstitutiveModel::fene_p,
       "T = 2 mu D + G (f c - I) with lambda c_UC + (f c - I) = 0, f = (L^2 - 3) / (L^2 - tr c) "
       "(FENE-P; Oldroyd-B as L^2 -> infinity)"}};
  if (solids) {
    options.push_back({"neo_hookean", ConstitutiveModel::neo_hookean,
                       "elastic particle T = G (B - I), B the Finger tensor (eqs. 2.21-2.22); no "
                       "interfacial tension"});
    options.push_back({"kelvin_voigt", ConstitutiveModel::kelvin_voigt,
                       "elastic particle with a solvent viscosity, T = 2 mu D + G (B - I); no "
                       "interfacial tension"});
  }
  return options;
}

/// The parameter keys of a non-Newtonian phase, in the case's units like
/// [matrix] viscosity, filling the ConstitutiveValues at `values`
/// (Constitutive::create checks them once more, and decides per model
/// what the keys' ranges cannot: e.g. mu > 0 for kelvin_voigt). `sub` is
/// the phase's subscript in the symbols ("m", "d"). Given for a model that
/// does not have it, a key is an error rather than ignored, so that a
/// wrong model name cannot silently drop a parameter. G and eta_p are
/// alternatives (case_config.cpp checks that exactly one is given).
template <class Target>
std::vector<Key<Target>> viscoelastic_keys(ConstitutiveValues Target::*values,
                                           const std::string& sub, bool solids) {
  const auto parameter = [values](std::optional<double> ConstitutiveValues::*member) {
    return field(values, member);
  };
  std::vector<std::string> with_solvent{"oldroyd_b", "giesekus", "fene_p"};
  std::vector<std::string> with_modulus = kViscoelasticLiquids;
  if (solids) {
    with_solvent.push_back("kelvin_voigt");
    with_modulus.push_back("neo_hookean");
    with_modulus.push_back("kelvin_voigt");
  }
  return {
      optional_number("solvent_viscosity", parameter(&ConstitutiveValues::solvent_viscosity),
                      required, Range::at_least(0),
                      fmt::format("mu_{}, the solvent viscosity ({})", sub,
                                  solids ? "ucm and neo_hookean are the models with mu = 0; > 0 "
                                           "for kelvin_voigt"
                                         : "ucm is the liquid with mu = 0"))
          .only_when("model", with_solvent),
      optional_number("polymer_viscosity", parameter(&ConstitutiveValues::polymer_viscosity),
                      Computed{"modulus * relaxation_time"}, Range::above(0),
                      fmt::format("eta_p = G_{0} lambda_{0}, the polymer viscosity; give this or "
                                  "modulus, not both. The zero-shear viscosity is eta_{0} = mu_{0} "
                                  "+ eta_p (eq. 2.9)",
                                  sub))
          .only_when("model", kViscoelasticLiquids),
      optional_number("modulus", parameter(&ConstitutiveValues::modulus),
                      Computed{solids ? "from polymer_viscosity or elastic_capillary_number"
                                      : "polymer_viscosity / relaxation_time"},
                      Range::above(0),
                      fmt::format("G_{}, the shear modulus: tau = G (c - I){}; give this or {}, "
                                  "not both",
                                  sub, solids ? " (c = B, the Finger tensor, for a particle)" : "",
                                  solids ? "polymer_viscosity (liquids) or "
                                           "elastic_capillary_number (elastic particles)"
                                         : "polymer_viscosity"))
          .only_when("model", with_modulus),
      optional_number("relaxation_time", parameter(&ConstitutiveValues::relaxation_time), required,
                      Range::above(0),
                      fmt::format("lambda_{}, the relaxation time; its Weissenberg number is "
                                  "lambda_{} gamma_dot. time.step may not exceed it",
                                  sub, sub))
          .only_when("model", kViscoelasticLiquids),
      optional_number("mobility", parameter(&ConstitutiveValues::mobility), required,
                      Range{0.0, 1.0, false, false},
                      fmt::format("alpha_{}, the Giesekus mobility (0 is Oldroyd-B)", sub))
          .only_when("model", {"giesekus"}),
      optional_number("extensibility", parameter(&ConstitutiveValues::extensibility), required,
                      Range::above(3),
                      fmt::format("L_{}^2, the FENE-P extensibility: the bound of tr c, whose "
                                  "rest value is 3 (f = (L^2 - 3) / (L^2 - tr c))",
                                  sub))
          .only_when("model", {"fene_p"})};
}

bool is_newtonian(ConstitutiveModel m) { return m == ConstitutiveModel::newtonian; }

Table<CaseConfig> matrix_table() {
  std::vector<Key<CaseConfig>> keys{
      choice("model", field(&CaseConfig::matrix_model), ConstitutiveModel::newtonian,
             model_options(false), "the constitutive model of the suspending liquid")
          // Newtonian cases print as they always did.
          .printed_if([](const CaseConfig& c) { return !is_newtonian(c.matrix_model); })
          .with_comment([](const CaseConfig& c) {
            return fmt::format("zero-shear viscosity eta_m = mu + G lambda = {}",
                               toml_float(c.matrix_viscosity));
          }),
      number("viscosity", field(&CaseConfig::matrix_viscosity), 1.0, Range::above(0),
             "eta_m, its viscosity")
          .only_when("model", {"newtonian"},
                     "a viscoelastic matrix's viscosity is eta_m = solvent_viscosity + "
                     "polymer_viscosity")};
  for (auto& k : viscoelastic_keys(&CaseConfig::matrix_parameters, "m", false))
    keys.push_back(std::move(k));
  return {"matrix",
          "The suspending liquid: Newtonian, or viscoelastic (thesis §2.2.1) with its parameters "
          "in the case's units. eta_m, the viscosity of Ca, Ca_e, lambda and p, is the "
          "zero-shear viscosity.",
          false, std::move(keys)};
}

Table<CaseConfig> flow_table() {
  const auto flow = [](auto member) { return field(&CaseConfig::flow, member); };
  return {
      "flow",
      "How the walls y = +-H/2 move: u = (+-u_w(t), 0, 0). Times are in the case's unit; with "
      "shear_rate = 1 that is 1/gamma_dot.",
      false,
      {choice("type", flow(&FlowConfig::type), FlowType::steady,
              {{"steady", FlowType::steady, "u_w = shear_rate H / 2 at all times"},
               {"start_up", FlowType::start_up,
                "at rest before t = 0, then u_w = shear_rate H / 2 (the run starts at t = 0 "
                "from rest: for t >= 0 the walls of \"steady\")"},
               {"cessation", FlowType::cessation,
                "u_w = shear_rate H / 2 until stop_time, then the walls stop (relaxation)"},
               {"oscillatory", FlowType::oscillatory,
                "u_w = (H/2) strain_amplitude frequency sin(frequency t)"}},
              "the wall-speed history u_w(t)"),
       number("shear_rate", field(&CaseConfig::shear_rate), 1.0, Range::at_least(0),
              "gamma_dot while the walls move (0 = at rest, steady only); the unit of Ca and "
              "of the redistribution factor. Oscillatory flow uses its amplitude "
              "strain_amplitude * frequency instead")
           .only_when("type", {"steady", "start_up", "cessation"})
           .with_comment([](const CaseConfig& c) {
             return fmt::format("wall velocity u_w = shear_rate * height / 2 = {}",
                                toml_float(c.wall_velocity()));
           }),
       number("stop_time", flow(&FlowConfig::stop_time), required, Range::above(0),
              "t at which the walls stop")
           .only_when("type", {"cessation"}),
       number("strain_amplitude", flow(&FlowConfig::strain_amplitude), required,
              Range::above(0), "gamma0: the strain is gamma0 (1 - cos(frequency t))")
           .only_when("type", {"oscillatory"}),
       number("frequency", flow(&FlowConfig::frequency), required, Range::above(0),
              "omega, angular (rad per time unit). Ca uses the shear-rate amplitude "
              "strain_amplitude * frequency as gamma_dot. time.step <= 2 pi / (10 frequency): "
              "at least 10 steps per period")
           .only_when("type", {"oscillatory"})
           .with_comment([](const CaseConfig& c) {
             return fmt::format("shear-rate amplitude strain_amplitude * frequency = {}",
                                toml_float(c.shear_rate));
           }),
       number("periods", flow(&FlowConfig::periods), 0.0, Range::at_least(0),
              "> 0: the run ends after this many periods 2 pi / frequency (it sets time.end: "
              "give this or time.end, not both; constant steps are shortened to a whole number "
              "per period); 0: time.end decides")
           .only_when("type", {"oscillatory"})
           .printed_if([](const CaseConfig& c) { return c.flow.periods > 0.0; })}};
}

Table<CaseConfig> mesh_table() {
  const auto sizing = [](auto member) { return field(&CaseConfig::sizing, member); };
  return {
      "mesh",
      "Resolution: element size graded from each interface to the walls (gmsh).",
      false,
      {integer("equator_nodes", sizing(&geometry::MeshSizing::equator_nodes), 40,
               Range::at_least(8),
               "P2 nodes around each object's equator (thesis: 28/40/50); fewer than 8 no longer "
               "describe a sphere"),
       number("far_size", sizing(&geometry::MeshSizing::far_size), 3.0, Range::above(0),
              "element size at the walls, far from the objects"),
       number("growth", sizing(&geometry::MeshSizing::growth), 0.4, Range::above(0),
              "the size grows as h0 + growth * distance from the interface"),
       optional_number("interior_growth", sizing(&geometry::MeshSizing::interior_growth),
                       Computed{"= growth"}, Range::at_least(0),
                       "growth of the size inside the objects, towards their centres; 0 = the "
                       "interface size throughout (resolves a particle's or viscoelastic drop's "
                       "stress, and gives a strongly deformed object interior vertices to move)"),
       boolean("optimize_high_order", sizing(&geometry::MeshSizing::optimize_high_order), true,
               "let gmsh untangle curved P2 elements"),
       optional_number("wall_size", sizing(&geometry::MeshSizing::wall_size),
                       Computed{"none: far_size reaches the walls"}, Range::above(0),
                       "element size at the walls y = +-H/2, growing away from them as "
                       "wall_size + growth * distance (the mesh is graded towards the walls as "
                       "towards the interfaces)"),
       optional_integer("gap_elements", sizing(&geometry::MeshSizing::gap_elements),
                        Computed{"2 across gaps narrower than one interface element"},
                        Range::at_least(1),
                        fmt::format("at least this many elements across the gap g between an "
                                    "object and a wall narrower than gap_elements interface "
                                    "elements: its elements follow its local width, on the "
                                    "object's surface facing the wall too. Unset: 2 across gaps "
                                    "narrower than one interface element only (wider ones keep "
                                    "the mesh graded from the interface, as before the key). An "
                                    "object closer to a wall than g_min = gap_elements h / {:g} "
                                    "(h = 4 pi a_min / equator_nodes, the interface element "
                                    "size) is refused",
                                    geometry::kMaxGapRefinement)),
       boolean("point_symmetric", sizing(&geometry::MeshSizing::point_symmetric), false,
               "mesh half the cell (y >= 0) and rotate it by 180 deg about z for the other "
               "half: the mesh then has the shear flow's point symmetry, and an object centred "
               "on the z axis (which it must be, turned about z only) does not drift across "
               "streamlines numerically (docs/confinement.md: the noise floor of v_p)"),
       boolean("point_symmetric_start", sizing(&geometry::MeshSizing::point_symmetric_start), false,
               "mesh the cell as point_symmetric with the one object on the z axis, then carry "
               "it to objects[0].centre by the mesh motion before the first step: the mesh is "
               "then the half turn's image of the mirror start's, and the numerical drift "
               "across streamlines grows from zero with the offset instead of being fixed by "
               "the mesh (migration near the centre plane; docs/confinement.md). One object; "
               "a remesh gives this up")
           .printed_if([](const CaseConfig& c) { return c.sizing.point_symmetric_start; })}};
}

Table<CaseConfig> solver_table() {
  return {
      "solver",
      "The Stokes solver; options go to PETSc under the prefix stokes_.",
      false,
      {choice("type", field(&CaseConfig::solver), SolverType::automatic,
              {{"auto", SolverType::automatic,
                "direct when the run is long enough to repay the factorisation (about "
                "100 (unknowns / 95000)^1.5 steps: docs/benchmarks/solver_crossover.md) and "
                "below 150000 unknowns (LU memory: 3.5 GB at 124k, 19 GB at 366k), iterative "
                "otherwise; the run prints which and why"},
               {"direct", SolverType::direct, "LU (MUMPS)"},
               {"iterative", SolverType::iterative, "GMRES with a Schur-complement fieldsplit"}},
              "how the saddle-point system is solved"),
       number("rtol", field(&CaseConfig::rtol), 1e-8, Range::open(0, 1),
              "relative residual tolerance of the iterative solver"),
       integer("max_iterations", field(&CaseConfig::max_iterations), 500, Range::at_least(1),
               "iteration limit of the iterative solver"),
       choice("initial_guess", field(&CaseConfig::initial_guess), InitialGuess::extrapolated,
              {{"extrapolated", InitialGuess::extrapolated,
                "the line through the last two steps' solutions, a step on: O(dt^2) from "
                "the answer where the flow changes smoothly (docs/stokes_engine.md: the "
                "iterations it saves)"},
               {"previous", InitialGuess::previous,
                "the last step's solution (softflow before 2026-12-07)"}},
              "where the Krylov solver starts each time step (the iterative method's, and "
              "the direct method's GMRES on kept LU factors); the answer is the same to the "
              "solver's tolerance")
           // Printed only when not the default: resolved cases (case.toml, checkpoints)
           // of runs from before the key stay as they were.
           .printed_if(
               [](const CaseConfig& c) { return c.initial_guess != InitialGuess::extrapolated; }),
       text("petsc_options", field(&CaseConfig::petsc_options), "",
            "extra PETSc options, passed as is, e.g. \"-stokes_ksp_monitor\", separated by "
            "spaces; each word is an option (-name) or the one value of the option before "
            "it (\"-stokes_ksp_type gmres\"): any other word, which PETSc would skip "
            "silently, is an error",
            petsc_options_problem)}};
}

Table<CaseConfig> output_table() {
  return {
      "output",
      "Where and what a run writes.",
      false,
      {text("directory", field(&CaseConfig::output_directory), Computed{"`\"output/<name>\"`"},
            fmt::format("where results go; a relative path is taken from the working directory, "
                        "not from the case file's folder. Its last part at most {} bytes (as "
                        "case.name), every part at most 255, the whole at most {}",
                        kMaxDirectoryNameBytes, kMaxDirectoryPathBytes),
            [](const std::string& s) -> std::string {
              if (s.empty()) return "must not be empty";
              return control_character_problem(s);
            }),
       boolean("fields", field(&CaseConfig::write_fields), true,
               "write velocity and pressure fields for ParaView (VTU/PVD)")}};
}

Table<CaseConfig> time_table() {
  const auto time = [](auto member) { return field(&CaseConfig::time, member); };
  // The bounds of adaptive steps are written out only for runs that have them.
  const auto adaptive = [](const CaseConfig& c) { return c.time.adaptive_tolerance > 0.0; };
  return {
      "time",
      "The time loop (thesis Steps 1-5).",
      false,
      {number("step", time(&TimeConfig::step), 0.005, Range::above(0),
              "dt: given (without adaptive_tolerance), every step's; with adaptive steps, the "
              "first. At most the shortest relaxation_time of a viscoelastic phase (its relaxation "
              "is explicit: stable below 4/3 of it), and for oscillatory flow at most 2 pi / (10 "
              "frequency), 10 steps per period"),
       number("end", time(&TimeConfig::end), 0.0, Range::at_least(0),
              "t_end; 0 = one Stokes solve of the initial state, no time loop (oscillatory "
              "flow: or flow.periods)")
           .printed_if([](const CaseConfig& c) { return !(c.flow.periods > 0.0); }),
       integer("fields_interval", time(&TimeConfig::fields_interval), 0, Range::at_least(0),
               "write fields every this many steps (0: at the end only)"),
       number("min_quality", time(&TimeConfig::min_quality), 0.02, Range::open(0, 1),
              "stop with a diagnosis once an element's quality falls below this"),
       number("max_volume_drift", time(&TimeConfig::max_volume_drift), 0.01, Range::open(0, 1),
              "stop with a diagnosis once an object's volume differs from its initial volume by "
              "more than this fraction"),
       number("ale_rebuild_quality", time(&TimeConfig::ale_rebuild_quality), 0.2,
              Range::right_open(0, 1),
              "below this element quality the mesh-motion operator is rebuilt on the current "
              "mesh (and after each further 5 % drop); 0 = never"),
       number("relocation_quality", time(&TimeConfig::relocation_quality), 0.2,
              Range::right_open(0, 1),
              "below this element quality the free nodes of the bad elements (not on an "
              "interface, a wall or a periodic face) are moved to improve them; 0 = never. "
              "Unset with mesh.point_symmetric_start: 0 (the search does not keep a carried "
              "mesh the mirror image of its mirror case's: docs/confinement.md)"),
       number("steady_tolerance", time(&TimeConfig::steady_tolerance), 0.0, Range::at_least(0),
              "> 0: stop at steady state, once every object's D, shape vector D (cos 2 theta, "
              "sin 2 theta) and centre velocity relative to the shear flow at the centre / "
              "(gamma_dot R) have each changed by at most "
              "this over the last steady_window (end is then the latest time); 0 = run to end"),
       number("steady_window", time(&TimeConfig::steady_window), 5.0, Range::above(0),
              "the time span steady_tolerance is measured over: longer than any oscillation "
              "that should not count as steady"),
       number("min_wall_gap", time(&TimeConfig::min_wall_gap), 0.0, Range::at_least(0),
              "> 0: the run ends (completed, the reason in summary.json) once an object's "
              "interface comes closer to a wall than this many of its radii (a migrating "
              "particle before the wall region the mesh cannot follow); 0 = never"),
       number("adaptive_tolerance", time(&TimeConfig::adaptive_tolerance), 0.0,
              Range::at_least(0),
              "> 0: adaptive steps, step is the first one; each step's largest distance between "
              "an interface node's predicted and corrected position, over the object's radius, "
              "is kept below this: a step above it is taken again, smaller, as is a step that "
              "fails (solver, mesh quality), down to step / 1000. 0 = constant steps. Neither "
              "this nor step given: 1e-3 in a run in time with objects, a flow without period "
              "and no remeshing (max_step then 0.04, or the shortest relaxation time, with a "
              "conformation to carry), constant steps otherwise; summary.json time_steps says "
              "which"),
       number("max_step", time(&TimeConfig::max_step), 0.0, Range::at_least(0),
              "adaptive steps: the largest step (0: none; needed with a viscoelastic phase or "
              "an elastic particle, and at most the shortest relaxation_time); adaptive "
              "steps also stay below 1 / (interface.redistribution_factor gamma_dot), the "
              "stability bound of the tangential redistribution")
           .printed_if(adaptive),
       number("max_growth", time(&TimeConfig::max_growth), 2.0, Range::open(1, 2.4),
              "adaptive steps: the largest ratio of a step to the one before (variable-step BDF2 "
              "is stable below 1 + sqrt(2))")
           .printed_if(adaptive)}};
}

Table<CaseConfig> checkpoint_table() {
  const auto checkpoint = [](auto member) { return field(&CaseConfig::checkpoint, member); };
  return {"checkpoint",
          "When a run in time saves its state (checkpoint.h5 in the output directory); also at "
          "the end, on SIGINT/SIGTERM/SIGUSR1 and before --wall-time-limit.",
          false,
          {integer("interval_steps", checkpoint(&CheckpointConfig::interval_steps), 0,
                   Range::at_least(0), "every this many steps (0: not by step count)"),
           number("interval_minutes", checkpoint(&CheckpointConfig::interval_minutes), 10.0,
                  Range::at_least(0), "at most this much wall time apart (0: not by time)")}};
}

Table<CaseConfig> bulk_stress_table() {
  const auto bulk = [](auto member) { return field(&CaseConfig::bulk_stress, member); };
  return {"bulk_stress",
          "The bulk stress of the suspension (thesis eq. 4.1) and its effective shear rate, "
          "averaged over a cube centred in the cell (objects counted by their centre), each "
          "step in bulk_stress.csv (docs/emulsions.md).",
          false,
          {number("box_side", bulk(&BulkStressConfig::box_side), 0.0, Range::at_least(0),
                  "side of the centred cube, at most the cell's length, height and width "
                  "(0: no bulk stress)"),
           number("fit_periods", bulk(&BulkStressConfig::fit_periods), 2.0, Range::above(0),
                  "oscillatory flow: G' and G'' (eqs. 4.6-4.7) are fitted to the last this many "
                  "periods of the shear stress and the shear rate (summary.json's moduli)")
               .printed_if([](const CaseConfig& c) { return c.bulk_stress.box_side > 0.0; })}};
}

Table<CaseConfig> conformation_table() {
  const auto conformation = [](auto member) { return field(&CaseConfig::conformation, member); };
  return {"conformation",
          "Numerics of the transport of log c in every phase that carries a conformation "
          "(viscoelastic liquids, elastic particles; docs/viscoelastic.md).",
          false,
          {choice("supg_tau", conformation(&ConformationConfig::supg_tau),
                  ConformationConfig::SupgTau::automatic,
                  {{"auto", ConformationConfig::SupgTau::automatic,
                    "transient in elastic solids (particles), steady in viscoelastic liquids"},
                   {"transient", ConformationConfig::SupgTau::transient,
                    "1 / tau^2 = (2 |w| / h)^2 + (2 / dt)^2 everywhere"},
                   {"steady", ConformationConfig::SupgTau::steady,
                    "tau = h / (2 |w|) whatever the step, everywhere (the thesis's; an elastic "
                    "particle's shape then does not converge as dt -> 0)"}},
                  "the SUPG parameter of the transport (w = u - u_mesh, h the element length)"),
           choice("stress_prediction", conformation(&ConformationConfig::stress_prediction),
                  physics::viscoelastic::StressPrediction::consistent,
                  {{"consistent", physics::viscoelastic::StressPrediction::consistent,
                    "the transport's own BDF step, plus the last step's defect against the "
                    "transported c: second order in dt"},
                   {"euler", physics::viscoelastic::StressPrediction::euler,
                    "one explicit Euler step from c_n (eq. 2.37, as the thesis; first order in "
                    "dt where the flow is not homogeneous)"}},
                  "the conformation the Stokes step's polymer stress is taken at "
                  "(docs/viscoelastic.md)"),
           boolean("devss_g", conformation(&ConformationConfig::devss_g), true,
                   "the DEVSS-G term theta (grad u - G_n) in every phase with a conformation "
                   "(theta = eta_p in a liquid, G dt in a solid); false: none, for studies of "
                   "its effect (G_n lags a step: first order in dt in a transient)")}};
}

Table<CaseConfig> emulsion_table() {
  const auto emulsion = [](auto member) { return field(&CaseConfig::emulsion, member); };
  return {
      "emulsion",
      "Many drops at random (docs/emulsions.md): the one [[objects]] entry, a sphere centred "
      "at the origin, is copied at centres placed by random sequential addition, no drop "
      "closer than min_gap to another or to a wall or periodic face.",
      false,
      {number("volume_fraction", emulsion(&EmulsionConfig::volume_fraction), 0.0,
              Range::right_open(0, 0.5),
              "volume fraction of the drops in the region they fill (0: no emulsion)"),
       integer("seed", emulsion(&EmulsionConfig::seed), 1, Range::at_least(0),
               "seed of the random placement: the same seed, the same drops"),
       number("min_gap", emulsion(&EmulsionConfig::min_gap), 0.0, Range::at_least(0),
              "smallest gap between drops and to the region's faces, in drop radii (0: one "
              "interface element); gaps below one interface element are refined by the mesh "
              "(mesh.gap_elements across, down to gap_elements / 64 interface elements); the "
              "cell's faces keep at least one interface element"),
       number("core_side", emulsion(&EmulsionConfig::core_side), 0.0, Range::at_least(0),
              "side of the centred cube the drops fill, the thesis's frame layout (0: the "
              "whole cell)"),
       choice("core_layout", emulsion(&EmulsionConfig::core_layout),
              EmulsionConfig::CoreLayout::inside,
              {{"inside", EmulsionConfig::CoreLayout::inside,
                "every drop wholly inside the core cube, min_gap from its faces (jams near phi = "
                "0.24 in a cube of side 8 R)"},
               {"centres", EmulsionConfig::CoreLayout::centres,
                "the drops' centres in the core cube, the drops crossing its faces, min_gap from "
                "the cell's (the thesis's: a whole-cell packing without the drops whose centres "
                "lie outside); phi counts the drops by their centre"}},
              "which drops fill the core cube (core_side > 0)")}};
}

Table<CaseConfig> remesh_table() {
  const auto remesh = [](auto member) { return field(&CaseConfig::remesh, member); };
  return {"remesh",
          "Meshing the deformed domain again during a run (docs/remeshing.md): the interfaces "
          "kept node for node or sampled afresh, the box and sizes of [cell] and [mesh], every "
          "field carried over; a line in the progress output, a row in remesh.csv and a "
          "checkpoint after each.",
          false,
          {number("quality", remesh(&RemeshConfig::quality), 0.0, Range::right_open(0, 1),
                  "remesh before a step once the worst element quality is below this (0: "
                  "never); above time.min_quality, which stops the run"),
           number("interval", remesh(&RemeshConfig::interval), 0.0, Range::at_least(0),
                  "remesh before a step once this much time has passed since the last remesh "
                  "or the start (0: never)"),
           number("gap_elements", remesh(&RemeshConfig::gap_elements), 0.0, Range::at_least(0),
                  "remesh before a step once an object's gap to a wall or to another object "
                  "is crossed by fewer elements than this (0: never); below "
                  "mesh.gap_elements, the count a remesh restores"),
           choice("interfaces", remesh(&RemeshConfig::interfaces),
                  geometry::InterfaceRemeshing::automatic,
                  {{"auto", geometry::InterfaceRemeshing::automatic,
                    "afresh where an interface no longer fits the case's sizes (a triangle more "
                    "than 2x off its size, or curved shape below 0.25: e.g. a particle's "
                    "interface refined towards a wall it has left), else kept"},
                   {"keep", geometry::InterfaceRemeshing::keep,
                    "node for node: the interface and its trackers' histories carry over exactly"},
                   {"resample", geometry::InterfaceRemeshing::resample,
                    "always afresh, on the curved surface at the case's sizes, the enclosed "
                    "volume restored to round-off"}},
                  "what a remesh does with each object's interface")}};
}

Table<CaseConfig> interface_table() {
  const auto interface = [](auto member) { return field(&CaseConfig::interface, member); };
  return {
      "interface",
      "Interface tracking (thesis §2.2.3, §2.3.2).",
      false,
      {number("redistribution_factor", interface(&InterfaceConfig::redistribution_factor), 10.0,
              Range::at_least(0),
              "k / gamma_dot of the tangential redistribution (thesis eq. 2.30); with "
              "gamma_dot = 0, k itself"),
       number("supg_beta", interface(&InterfaceConfig::supg_beta), 0.5, Range::at_least(0),
              "beta of the SUPG parameter tau = beta h / (2 U_t); 0.5 for P2"),
       boolean("semi_implicit_tension", interface(&InterfaceConfig::semi_implicit_tension), true,
               "tension at the end-of-step interface position: no capillary time-step limit; "
               "false = the thesis's explicit tension")}};
}

// ---- [[objects]] ----

Table<ObjectConfig> objects_table() {
  const auto geometry = [](auto member) { return field(&ObjectConfig::geometry, member); };
  // A sphere's one size fills all three semi-axes.
  const Field<ObjectConfig, double> radius{
      [](const ObjectConfig& o) { return o.geometry.semi_axes.x(); },
      [](ObjectConfig& o, const double& r) { o.geometry.semi_axes.setConstant(r); }};
  const std::string no_tension = "an elastic particle has no interfacial tension";
  Table<ObjectConfig> table{
      "objects",
      "One entry per suspended object (a drop or an elastic particle); none = the undisturbed "
      "shear flow. With one object the mesh is translated along x with it every step (Step 2), "
      "so it never drifts towards the periodic faces; with several the mesh is not translated "
      "(it can follow only one), so objects moving relative to each other deform the mesh, and "
      "a run lasts until they have travelled about an element size near their interfaces "
      "(time.min_quality stops it with a diagnosis). timeseries.csv has one row per object and "
      "step.",
      true,
      {choice("shape", geometry(&geometry::ObjectSpec::shape), geometry::ObjectShape::sphere,
              {{"sphere", geometry::ObjectShape::sphere, ""},
               {"ellipsoid", geometry::ObjectShape::ellipsoid, ""}},
              "the initial shape"),
       vector3("centre", geometry(&geometry::ObjectSpec::centre), Eigen::Vector3d(0, 0, 0),
               Range::any(), "the centre [x, y, z]"),
       number("radius", radius, 1.0, Range::above(0), "R").only_when("shape", {"sphere"}),
       vector3("semi_axes", geometry(&geometry::ObjectSpec::semi_axes), required,
               Range::above(0),
               "semi-axes [a, b, c] along the body axes. The interface elements follow the "
               "smallest, so a_max / a_min is at most min(N / 8, 150 / N), N = "
               "mesh.equator_nodes (so at most 4.29, at N = 35): beyond N / 8 the mesh does "
               "not resolve the sharpest curvature, beyond 150 / N gmsh does not finish in "
               "reasonable time")
           .only_when("shape", {"ellipsoid"}),
       vector3("rotation_deg", geometry(&geometry::ObjectSpec::rotation_deg),
               Eigen::Vector3d(0, 0, 0), Range{-360.0, 360.0, false, false},
               "body orientation in degrees: R = Rz(rz) Ry(ry) Rx(rx); each angle within one turn "
               "either way, which gives every orientation (an angle beyond is refused, not "
               "reduced: 1e300 degrees is a typing error, and has no digits left that place it)")
           .only_when("shape", {"ellipsoid"}),
       choice("model", field(&ObjectConfig::model), ConstitutiveModel::newtonian,
              model_options(true),
              "the constitutive model: a Newtonian or viscoelastic drop, or an elastic particle")
           .printed_if([](const ObjectConfig& o) { return !is_newtonian(o.model); })
           .with_comment([](const ObjectConfig& o) -> std::string {
             if (is_elastic_solid(o.model)) return "";
             return fmt::format("viscosity ratio eta_d / eta_m = {}, eta_d = mu + G lambda",
                                toml_float(o.viscosity_ratio));
           }),
       number("viscosity_ratio", field(&ObjectConfig::viscosity_ratio), 1.0, Range::above(0),
              "lambda = eta_d / eta_m")
           .only_when("model", {"newtonian"},
                      "a viscoelastic object's viscosities are given in the case's units "
                      "(solvent_viscosity, polymer_viscosity)")}};
  // The interface, after the phase's own parameters.
  std::vector<Key<ObjectConfig>> tension{
      optional_number(
          "capillary_number", field(&ObjectConfig::capillary_number),
          Computed{"0.1 unless interfacial_tension is given"}, Range::above(0),
          "Ca = eta_m gamma_dot R / Gamma with R = (abc)^(1/3) and gamma_dot = flow.shear_rate "
          "(oscillatory: strain_amplitude * frequency); sets Gamma, so it needs gamma_dot > 0. "
          "Give this or interfacial_tension, not both")
          .only_when("model", kLiquids, no_tension)
          // Written as given, so that re-reading computes the very same Gamma.
          .with_comment([](const ObjectConfig& o) {
            return "interfacial_tension = " + toml_float(o.interfacial_tension);
          }),
      number("interfacial_tension", field(&ObjectConfig::interfacial_tension),
             Computed{"from capillary_number"}, Range::at_least(0),
             "Gamma, the interfacial tension (0: none); give this or capillary_number, not both")
          .only_when("model", kLiquids, no_tension)
          .printed_if([](const ObjectConfig& o) { return !o.capillary_number; })};
  auto viscoelastic = viscoelastic_keys(&ObjectConfig::parameters, "d", true);
  // Ca_e right after the modulus it stands for.
  const auto after_modulus =
      std::find_if(viscoelastic.begin(), viscoelastic.end(),
                   [](const Key<ObjectConfig>& k) { return k.name == "modulus"; }) +
      1;
  viscoelastic.insert(
      after_modulus,
      optional_number("elastic_capillary_number", field(&ObjectConfig::elastic_capillary_number),
                      Computed{"eta_m gamma_dot / modulus"}, Range::above(0),
                      "Ca_e = eta_m gamma_dot / G with gamma_dot = flow.shear_rate (oscillatory: "
                      "strain_amplitude * frequency) and eta_m the matrix's zero-shear viscosity; "
                      "sets G, so it needs gamma_dot > 0. Give this or modulus, not both")
          .only_when("model", {"neo_hookean", "kelvin_voigt"})
          // Written as given, so that re-reading computes the very same G.
          .with_comment([](const ObjectConfig& o) {
            return o.parameters.modulus ? "modulus = " + toml_float(*o.parameters.modulus) : "";
          }));
  // The modulus an elastic particle's Ca_e set is not written: Ca_e is.
  for (auto& k : viscoelastic)
    if (k.name == "modulus")
      k = std::move(k).printed_if(
          [](const ObjectConfig& o) { return !o.elastic_capillary_number; });
  for (auto& k : viscoelastic) table.keys.push_back(std::move(k));
  for (auto& k : tension) table.keys.push_back(std::move(k));
  // Navier slip, last: a property of the interface like the tension. It
  // applies to every model so that slip = 0 may be written for any object;
  // case_config.cpp refuses slip > 0 on an elastic particle.
  table.keys.push_back(
      number("slip", field(&ObjectConfig::slip), 0.0, Range::at_least(0),
             "alpha, the Navier slip coefficient of the interface, made dimensionless through "
             "R / eta_m: (I - nn)(u_m - u_d) = alpha (I - nn)(sigma_m n), n the outward normal, "
             "so the dimensional coefficient is alpha R / eta_m (R = (abc)^(1/3), eta_m the "
             "matrix's zero-shear viscosity). 0 = no slip; drops only (an elastic particle "
             "takes 0)")
          // Cases without slip print as they always did.
          .printed_if([](const ObjectConfig& o) { return o.slip != 0.0; }));
  table.keys.push_back(
      choice("initial_deformation", field(&ObjectConfig::initial_deformation),
             InitialDeformation::none,
             {{"none", InitialDeformation::none, ""},
              {"taylor", InitialDeformation::taylor,
               "the steady ellipsoid of small-deformation theory"}},
             "\"taylor\": a Newtonian drop in steady shear starts as the ellipsoid of "
             "small-deformation theory (Taylor's D, Chaffey-Brenner's angle, the vorticity axis "
             "kept, volume kept): the sphere's mesh deformed by that linear map, extended into "
             "the liquid by the mesh motion, so that the run keeps the sphere's mesh and starts "
             "near the steady shape (whether it gets there sooner depends on the mesh: "
             "docs/time_stepping.md)")
          .only_when("shape", {"sphere"})
          .printed_if([](const ObjectConfig& o) {
            return o.initial_deformation != InitialDeformation::none;
          }));
  return table;
}

CaseKeys build() {
  CaseKeys k;
  k.tables = {case_table(),       cell_table(),      matrix_table(),       flow_table(),
              mesh_table(),       solver_table(),    output_table(),       time_table(),
              checkpoint_table(), interface_table(), conformation_table(), bulk_stress_table(),
              emulsion_table(),   remesh_table()};
  k.objects = objects_table();
  // [[objects]] after [flow]: the objects come after what sets their Gamma.
  for (const auto& t : k.tables) {
    k.schema.tables.push_back(t.info());
    if (t.name == "flow") k.schema.tables.push_back(k.objects.info());
  }
  k.schema.aliases = {
      {"ca", "objects", "capillary_number"},
      {"capillary", "objects", "capillary_number"},
      {"gamma", "objects", "interfacial_tension"},
      {"sigma", "objects", "interfacial_tension"},
      {"surface_tension", "objects", "interfacial_tension"},
      {"lambda", "objects", "viscosity_ratio"},
      {"center", "objects", "centre"},
      {"axes", "objects", "semi_axes"},
      {"gamma_dot", "flow", "shear_rate"},
      {"omega", "flow", "frequency"},
      {"gamma0", "flow", "strain_amplitude"},
      {"eta", "matrix", "viscosity"},
      {"eta_m", "matrix", "viscosity"},
      // The constitutive keys, by the symbols of thesis §2.2 (per table:
      // [matrix] and [[objects]] each have their own). Not "alpha": in
      // [[objects]] it names both the Giesekus mobility (alpha_d) and the
      // slip coefficient (alpha), so it suggests neither; "navier_slip" or
      // "slip_coefficient" find `slip` by containing it.
      {"type", "matrix", "model"},
      {"type", "objects", "model"},
      {"constitutive", "matrix", "model"},
      {"constitutive", "objects", "model"},
      {"mu", "matrix", "solvent_viscosity"},
      {"mu", "objects", "solvent_viscosity"},
      {"mu_m", "matrix", "solvent_viscosity"},
      {"mu_d", "objects", "solvent_viscosity"},
      {"mu_s", "matrix", "solvent_viscosity"},
      {"mu_s", "objects", "solvent_viscosity"},
      {"eta_s", "matrix", "solvent_viscosity"},
      {"eta_s", "objects", "solvent_viscosity"},
      {"eta_p", "matrix", "polymer_viscosity"},
      {"eta_p", "objects", "polymer_viscosity"},
      {"g", "matrix", "modulus"},
      {"g", "objects", "modulus"},
      {"g_m", "matrix", "modulus"},
      {"g_d", "objects", "modulus"},
      {"g_p", "objects", "modulus"},
      {"lambda", "matrix", "relaxation_time"},
      {"lambda_m", "matrix", "relaxation_time"},
      {"lambda_d", "objects", "relaxation_time"},
      {"lambda_p", "matrix", "relaxation_time"},
      {"lambda_p", "objects", "relaxation_time"},
      {"ca_e", "objects", "elastic_capillary_number"},
  };
  return k;
}

}  // namespace

std::vector<std::string> petsc_option_words(std::string_view options) {
  // As PetscOptionsInsertString's tokenizer: words separated by runs of
  // spaces; a word that begins with '"' runs to the next '"' (without them).
  std::vector<std::string> words;
  std::size_t i = 0;
  while (i < options.size()) {
    while (i < options.size() && options[i] == ' ') ++i;
    if (i == options.size()) break;
    const char end = options[i] == '"' ? '"' : ' ';
    if (end == '"') ++i;
    const std::size_t stop = std::min(options.find(end, i), options.size());
    words.emplace_back(options.substr(i, stop - i));
    i = stop + 1;
  }
  return words;
}

bool is_petsc_option_name(std::string_view word) {
  // PetscOptionsValidKey: "-" (or "--") and a letter, and not a number
  // that strtod reads whole ("-inf", "-nan"; "-1e3" has no letter after
  // the dash).
  if (word.size() < 2 || word[0] != '-') return false;
  std::string_view key = word;
  if (key[1] == '-') key.remove_prefix(1);
  if (key.size() < 2 || !std::isalpha(static_cast<unsigned char>(key[1]))) return false;
  const std::string text(key);
  char* end = nullptr;
  (void)std::strtod(text.c_str(), &end);
  if (end != text.c_str() && !(*end == '_' || std::isalnum(static_cast<unsigned char>(*end))))
    return false;
  return true;
}

std::string petsc_words_problem(const std::vector<std::string>& words) {
  bool after_option = false;
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (is_petsc_option_name(words[i])) {
      after_option = true;
      continue;
    }
    if (after_option) {  // the value of the option before it
      after_option = false;
      continue;
    }
    // A stray word after a value follows an option and its value: a value
    // needs an option before it, and an option would have taken this word.
    const std::string where =
        i == 0 ? "it comes first"
               : fmt::format("'{}' already takes '{}'", words[i - 2], words[i - 1]);
    const std::string fix = words[i][0] == '-' ? "correct or remove it"
                                               : fmt::format("write '-{}' or remove it", words[i]);
    return fmt::format(
        "the word '{}' (word {}) is neither an option ('-' and a letter, e.g. "
        "-stokes_ksp_monitor) nor the value of the option before it ({}): PETSc would skip it "
        "silently; {}",
        words[i], i + 1, where, fix);
  }
  return "";
}

bool is_plain_name(std::string_view name) {
  if (name.empty() || name == "." || name == "..") return false;
  if (name.find_first_not_of(' ') == std::string_view::npos) return false;  // only spaces
  return std::none_of(name.begin(), name.end(), [](char c) {
    return c == '/' || c == '\\' || static_cast<unsigned char>(c) < 0x20;
  });
}

const schema::Table<CaseConfig>* CaseKeys::table(std::string_view name) const {
  for (const auto& t : tables)
    if (t.name == name) return &t;
  return nullptr;
}

const CaseKeys& case_keys() {
  // The schema's TableInfo point into the tables: built in place, never copied.
  static const CaseKeys keys = build();
  return keys;
}

std::string case_file_keys_markdown() {
  std::string s =
      "# Case-file keys\n\n"
      "Generated by `softflow keys > docs/case_file_keys.md` from the declarations in\n"
      "`src/softflow/io/case_keys.cpp`; do not edit by hand (a unit test checks that the two "
      "agree).\n\n"
      "Every key is optional unless marked required; a key that does not apply (e.g. `radius` "
      "of an ellipsoid, `stop_time` of steady flow) is an error rather than ignored. "
      "`softflow check CASE.toml` prints a case with every default filled in; "
      "`examples/drop_shear.toml` is a commented example. Any key may be a list of values, "
      "which makes the file a parameter sweep (`softflow sweep`).\n";
  for (const auto& t : case_keys().schema.tables) {
    s += '\n';
    s += schema::markdown(t);
  }
  return s;
}

}  // namespace softflow::io
