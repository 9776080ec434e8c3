#include "softflow/simulation/frequency_response.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>

#include <fmt/format.h>

#include "softflow/analysis/box_clipping.hpp"
#include "softflow/analysis/theory/oldroyd_emulsion.hpp"
#include "softflow/common/error.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/fem/tabulation.hpp"
#include "softflow/io/report_table.hpp"
#include "softflow/io/output_directory.hpp"
#include "softflow/la/petsc.hpp"
#include "softflow/physics/interface/interface_mesh.hpp"
#include "softflow/physics/stokes/oscillatory_response.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/simulation/case_flow.hpp"
#include "softflow/simulation/run_support.hpp"
#include "softflow/simulation/stop_requests.hpp"

namespace softflow::simulation {

namespace fs = std::filesystem;
using Complex = std::complex<double>;

namespace {

using Clock = std::chrono::steady_clock;

/// int 2 D_xy of the response over the pieces (reference coordinates) of tetrahedron t.
Complex shear_rate_integral(const mesh::Mesh& mesh, const fem::DofMap& dofs, const physics::OscillatoryResponse& r,
                            int t, const std::vector<analysis::Tetrahedron>& pieces) {
  static const element::QuadratureRule rule = element::tetrahedron_rule(2);  // 2 D_xy of P2: degree 1
  const auto element_dofs = dofs.element_dofs(t);  // velocity first, 3 k + i
  Complex sum(0.0, 0.0);
  analysis::for_each_point_in_pieces(fem::tet_nodes(mesh, t), pieces, rule,
                                     [&](const Eigen::Vector3d&, double w, const auto& grad) {
                                       Complex d(0.0, 0.0);  // du_x/dy + du_y/dx
                                       for (int k = 0; k < 10; ++k) {
                                         const int ux = element_dofs[3 * k], uy = element_dofs[3 * k + 1];
                                         d += Complex(r.real[ux], r.imaginary[ux]) * grad(k, 1) +
                                              Complex(r.real[uy], r.imaginary[uy]) * grad(k, 0);
                                       }
                                       sum += w * d;
                                     });
  return sum;
}

/// G' R / Gamma and G'' / (eta_m omega) of eta* / eta_m at omega*.
std::pair<double, double> scaled_moduli(Complex relative_viscosity, double omega_star) {
  return {-omega_star * relative_viscosity.imag(), relative_viscosity.real()};
}

}  // namespace

void check_response_case(const io::CaseConfig& config, const std::vector<double>& frequencies,
                         const std::vector<double>& cube_sides) {
  using physics::viscoelastic::ConstitutiveModel;
  if (config.matrix_model != ConstitutiveModel::newtonian)
    throw InputError("matrix.model: the frequency-domain response takes a Newtonian matrix (allowed: "
                     "\"newtonian\"); a viscoelastic matrix runs in the time domain with softflow run");
  if (config.objects.empty())
    throw InputError("no [[objects]]: the frequency-domain response is that of drops; give at least one");
  for (std::size_t k = 0; k < config.objects.size(); ++k) {
    const auto& o = config.objects[k];
    const std::string key = fmt::format("objects[{}]", k + 1);
    if (o.model != ConstitutiveModel::newtonian)
      throw InputError(fmt::format("{}.model: the response is linearised about Newtonian drops at rest (allowed: "
                                   "\"newtonian\")", key));
    if (o.geometry.shape != geometry::ObjectShape::sphere)
      throw InputError(fmt::format("{}.shape: the drops rest as spheres (allowed: \"sphere\")", key));
    if (o.initial_deformation != io::InitialDeformation::none)
      throw InputError(fmt::format("{}.initial_deformation: the response is about the resting sphere (allowed: "
                                   "\"none\")", key));
    if (!(o.interfacial_tension > 0.0))
      throw InputError(
          fmt::format("{}.interfacial_tension = {}: a drop needs a tension > 0 (it is the "
                      "emulsion's elasticity)",
                      key, o.interfacial_tension));
  }
  const double smallest = std::min({config.box.length, config.box.height, config.box.width});
  for (double side : cube_sides)
    if (!(side > 0.0) || side > smallest)
      throw InputError(
          fmt::format("--cube-sides {}: a centred cube's side must be > 0 and fit in the cell "
                      "(at most {:g}, its smallest dimension)",
                      side, smallest));
  if (frequencies.empty() && !(config.flow.type == io::FlowType::oscillatory && config.flow.frequency > 0.0))
    throw InputError("flow.frequency: no frequency given: set flow.type = \"oscillatory\" with a frequency, or "
                     "pass --frequency");
  for (double w : frequencies)
    if (!(w > 0.0) || !std::isfinite(w))
      throw InputError(fmt::format("--frequency {}: the angular frequency must be a finite number > 0", w));
}

namespace {

/// The case's drops as the linearised problem sees them, the walls moving
/// with shear-rate amplitude 1 (the response is linear: c and eta* are ratios to it).
physics::OscillatoryProblem oscillatory_problem(const io::CaseConfig& config, const mesh::Mesh& mesh) {
  physics::OscillatoryProblem problem;
  problem.viscosity = {config.matrix_viscosity};
  for (const auto& o : config.objects) {
    problem.viscosity.push_back(o.viscosity_ratio * config.matrix_viscosity);
    problem.interfacial_tension.push_back(o.interfacial_tension);
    problem.radius.push_back(io::mean_radius(o.geometry));
    problem.slip.coefficient.push_back(io::navier_slip_coefficient(config, o));
  }
  problem.boundary_velocity = [](const Eigen::Vector3d& x) { return Eigen::Vector3d(x.y(), 0.0, 0.0); };
  problem.pressure_gauge_node = physics::default_pressure_gauge_node(mesh);
  return problem;
}

/// A centred cube as the time domain's bulk-stress module averages over it:
/// the drops whose centre lies in it counted whole, the matrix clipped to it.
struct CubeAverage {
  analysis::Box box;
  std::vector<bool> counted;  // per region: a drop the cube counts
  double counted_volume = 0.0;
  int counted_drops = 0;
  /// Each element of the cube's volume term with its pieces in reference coordinates.
  std::vector<std::pair<int, std::vector<analysis::Tetrahedron>>> pieces;

  CubeAverage(const mesh::Mesh& mesh, double side,
              const std::vector<physics::SurfaceIntegrals>& drops)
      : box(analysis::centred_cube(side)), counted(mesh.n_objects + 1, false) {
    for (int k = 1; k <= mesh.n_objects; ++k) {
      counted[k] = box.contains(drops[k - 1].centre_of_volume());
      if (counted[k]) {
        counted_volume += drops[k - 1].volume;
        ++counted_drops;
      }
    }
    for (int t = 0; t < mesh.n_tets(); ++t) {
      const int region = mesh.tet_region[t];
      if (region > 0 && !counted[region]) continue;
      auto in_box = region > 0
                        ? std::vector<analysis::Tetrahedron>{analysis::reference_tetrahedron()}
                        : analysis::reference_pieces_in_box(fem::tet_nodes(mesh, t), box);
      if (!in_box.empty()) pieces.emplace_back(t, std::move(in_box));
    }
  }

  /// phi, drops, the moduli and Oldroyd's at this cube's phi, from the
  /// drops' stresslets S_xy (index k - 1): eta* = <sigma_xy> / <2 D_xy>, with
  /// <sigma_xy> V = eta_m <2 D_xy> V + the counted stresslets.
  [[nodiscard]] CubeModuli moduli(const io::CaseConfig& config, const mesh::Mesh& mesh,
                                  const fem::DofMap& dofs, const physics::OscillatoryResponse& r,
                                  const std::vector<Complex>& stresslets, double omega_star) const {
    Complex shear(0.0, 0.0), counted_stresslets(0.0, 0.0);
    for (const auto& [t, in_box] : pieces) shear += shear_rate_integral(mesh, dofs, r, t, in_box);
    for (int k = 1; k <= mesh.n_objects; ++k)
      if (counted[k]) counted_stresslets += stresslets[k - 1];
    CubeModuli m;
    m.side = box.hi.x() - box.lo.x();
    std::tie(m.storage, m.loss) =
        scaled_moduli(1.0 + counted_stresslets / (config.matrix_viscosity * shear), omega_star);
    m.phi = counted_volume / box.volume();
    m.drops = counted_drops;
    const io::ObjectConfig& first = config.objects.front();
    const auto theory =
        analysis::theory::oldroyd_moduli(first.viscosity_ratio, m.phi, omega_star, first.slip);
    m.oldroyd_storage = theory.storage;
    m.oldroyd_loss = theory.loss;
    return m;
  }
};

/// Where the moduli are averaged: the whole cell (every drop), the centred
/// cube of bulk_stress.box_side if any, and the cubes of a side study.
struct Averaging {
  double cell_volume = 0.0;
  double drops_volume = 0.0;
  std::optional<CubeAverage> box;
  std::vector<CubeAverage> study;

  Averaging(const io::CaseConfig& config, const mesh::Mesh& mesh,
            const std::vector<double>& cube_sides) {
    cell_volume = mesh.box.length * mesh.box.height * mesh.box.width;
    std::vector<physics::SurfaceIntegrals> drops;
    for (int k = 1; k <= mesh.n_objects; ++k) {
      const auto surface = physics::extract_interface(mesh, k);
      drops.push_back(
          physics::surface_integrals(surface, physics::interface_positions(surface, mesh)));
      drops_volume += drops.back().volume;
    }
    if (config.bulk_stress.box_side > 0.0) box.emplace(mesh, config.bulk_stress.box_side, drops);
    for (double side : cube_sides) study.emplace_back(mesh, side, drops);
  }
};

/// One frequency's moduli from its solution.
ResponsePoint measure(const io::CaseConfig& config, const mesh::Mesh& mesh, const physics::OscillatorySystem& system,
                      const physics::OscillatoryProblem& problem, const physics::OscillatoryResponse& r,
                      const Averaging& where) {
  const io::ObjectConfig& first = config.objects.front();
  const double eta_m = config.matrix_viscosity;
  ResponsePoint p;
  p.omega = problem.omega;
  p.omega_star = problem.omega * eta_m * io::mean_radius(first.geometry) / first.interfacial_tension;
  p.seconds = r.assembly_seconds + r.solve.seconds;
  p.iterations = r.solve.iterations;
  p.inner_solves = r.inner_solves;
  p.inner_iterations = r.inner_iterations;
  std::vector<Complex> each(mesh.n_objects);
  Complex stresslets(0.0, 0.0);
  for (int k = 1; k <= mesh.n_objects; ++k)
    stresslets += each[k - 1] = system.stresslet(problem, r, k)(0, 1);
  p.intrinsic_viscosity = stresslets / (eta_m * where.drops_volume);
  p.cell_phi = where.drops_volume / where.cell_volume;
  std::tie(p.cell_storage, p.cell_loss) = scaled_moduli(1.0 + stresslets / (eta_m * where.cell_volume), p.omega_star);
  p.oldroyd_intrinsic_viscosity =
      analysis::theory::oldroyd_dilute_coefficient(first.viscosity_ratio, p.omega_star, first.slip);
  const auto cell_theory =
      analysis::theory::oldroyd_moduli(first.viscosity_ratio, p.cell_phi, p.omega_star, first.slip);
  p.oldroyd_cell_storage = cell_theory.storage;
  p.oldroyd_cell_loss = cell_theory.loss;
  if (where.box) p.box = where.box->moduli(config, mesh, system.dofs(), r, each, p.omega_star);
  for (const auto& cube : where.study)
    p.cubes.push_back(cube.moduli(config, mesh, system.dofs(), r, each, p.omega_star));
  return p;
}

std::string response_csv(const std::vector<ResponsePoint>& points) {
  std::string csv =
      "omega,omega_star,c_real,c_imag,oldroyd_c_real,oldroyd_c_imag,cell_phi,cell_G_storage_R_over_Gamma,"
      "cell_G_loss_over_eta_m_omega,oldroyd_cell_G_storage,oldroyd_cell_G_loss,box_phi,box_drops,"
      "box_G_storage_R_over_Gamma,box_G_loss_over_eta_m_omega,oldroyd_box_G_storage,oldroyd_box_G_loss,seconds,"
      "iterations,inner_solves,inner_iterations\n";
  for (const auto& p : points) {
    const auto& b = p.box;  // its six columns empty without a cube
    const auto box_number = [&](double CubeModuli::*member) {
      return b ? io::table_number((*b).*member, 10) : std::string();
    };
    csv +=
        fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
                    io::table_number(p.omega, 10), io::table_number(p.omega_star, 10),
                    io::table_number(p.intrinsic_viscosity.real(), 10),
                    io::table_number(p.intrinsic_viscosity.imag(), 10),
                    io::table_number(p.oldroyd_intrinsic_viscosity.real(), 10),
                    io::table_number(p.oldroyd_intrinsic_viscosity.imag(), 10),
                    io::table_number(p.cell_phi, 10), io::table_number(p.cell_storage, 10),
                    io::table_number(p.cell_loss, 10), io::table_number(p.oldroyd_cell_storage, 10),
                    io::table_number(p.oldroyd_cell_loss, 10), box_number(&CubeModuli::phi),
                    b ? std::to_string(b->drops) : std::string(), box_number(&CubeModuli::storage),
                    box_number(&CubeModuli::loss), box_number(&CubeModuli::oldroyd_storage),
                    box_number(&CubeModuli::oldroyd_loss), io::table_number(p.seconds, 4),
                    p.iterations, p.inner_solves, p.inner_iterations);
  }
  return csv;
}

std::string cubes_csv(const std::vector<ResponsePoint>& points) {
  std::string csv =
      "omega,omega_star,side,phi,drops,G_storage_R_over_Gamma,G_loss_over_eta_m_omega,"
      "oldroyd_G_storage,oldroyd_G_loss\n";
  for (const auto& p : points)
    for (const auto& c : p.cubes)
      csv += fmt::format("{},{},{},{},{},{},{},{},{}\n", io::table_number(p.omega, 10),
                         io::table_number(p.omega_star, 10), io::table_number(c.side, 10),
                         io::table_number(c.phi, 10), c.drops, io::table_number(c.storage, 10),
                         io::table_number(c.loss, 10), io::table_number(c.oldroyd_storage, 10),
                         io::table_number(c.oldroyd_loss, 10));
  return csv;
}

std::string response_markdown(const io::CaseConfig& config, int drops, int unknowns,
                              const std::vector<ResponsePoint>& points) {
  const bool has_box = points.front().box.has_value();
  std::string md = fmt::format(
      "# Frequency response of {}\n\n"
      "One complex Stokes solve per frequency about the resting spherical drops (softflow response; "
      "docs/emulsions.md): {} drops, lambda = {:g} (objects[1]), {} real unknowns. c: the drops' stresslets "
      "summed over eta_m gamma_dot V_d (the complex intrinsic viscosity), beside the dilute limit of "
      "Oldroyd's emulsion; the cell's moduli from its walls (phi = {:.5g}) beside Oldroyd's at that phi{}.\n\n"
      "| omega | omega* | c | Oldroyd c (dilute) | G' R/Gamma (cell) | Oldroyd | G''/(eta_m omega) (cell) | Oldroyd |{}\n"
      "|---|---|---|---|---|---|---|---|{}\n",
      config.name, drops, config.objects.front().viscosity_ratio, unknowns, points.front().cell_phi,
      has_box ? fmt::format("; the centred cube of side {:g} as softflow moduli averages it", config.bulk_stress.box_side)
              : std::string(),
      has_box ? " phi (cube) | G' R/Gamma (cube) | Oldroyd | G''/(eta_m omega) (cube) | Oldroyd |" : "",
      has_box ? "---|---|---|---|---|" : "");
  for (const auto& p : points) {
    md += fmt::format("| {} | {} | {:.5f} {:+.5f} i | {:.5f} {:+.5f} i | {} | {} | {} | {} |",
                      io::table_number(p.omega, 5), io::table_number(p.omega_star, 5),
                      p.intrinsic_viscosity.real(), p.intrinsic_viscosity.imag(),
                      p.oldroyd_intrinsic_viscosity.real(), p.oldroyd_intrinsic_viscosity.imag(),
                      io::table_number(p.cell_storage, 5),
                      io::table_number(p.oldroyd_cell_storage, 5), io::table_number(p.cell_loss, 5),
                      io::table_number(p.oldroyd_cell_loss, 5));
    if (const auto& b = p.box)
      md += fmt::format(" {} | {} | {} | {} | {} |", io::table_number(b->phi, 4),
                        io::table_number(b->storage, 5), io::table_number(b->oldroyd_storage, 5),
                        io::table_number(b->loss, 5), io::table_number(b->oldroyd_loss, 5));
    md += "\n";
  }
  return md;
}

nlohmann::json cube_json(const CubeModuli& c) {
  return {{"side", c.side},
          {"phi", c.phi},
          {"drops", c.drops},
          {"storage", c.storage},
          {"loss", c.loss},
          {"oldroyd_storage", c.oldroyd_storage},
          {"oldroyd_loss", c.oldroyd_loss}};
}

CubeModuli cube_from_json(const nlohmann::json& j) {
  return {j.at("side"),        j.at("phi"),  j.at("drops"),
          j.at("storage"),     j.at("loss"), j.at("oldroyd_storage"),
          j.at("oldroyd_loss")};
}

/// A solved frequency as the record of finished frequencies keeps it: every
/// field, doubles to the bit (nlohmann writes them round-trip exact).
nlohmann::json point_json(const ResponsePoint& p) {
  nlohmann::json cubes = nlohmann::json::array();
  for (const auto& c : p.cubes) cubes.push_back(cube_json(c));
  return {{"omega", p.omega},
          {"omega_star", p.omega_star},
          {"intrinsic_viscosity", {p.intrinsic_viscosity.real(), p.intrinsic_viscosity.imag()}},
          {"cell_phi", p.cell_phi},
          {"cell_storage", p.cell_storage},
          {"cell_loss", p.cell_loss},
          {"box", p.box ? cube_json(*p.box) : nlohmann::json()},
          {"oldroyd_intrinsic_viscosity",
           {p.oldroyd_intrinsic_viscosity.real(), p.oldroyd_intrinsic_viscosity.imag()}},
          {"oldroyd_cell_storage", p.oldroyd_cell_storage},
          {"oldroyd_cell_loss", p.oldroyd_cell_loss},
          {"cubes", cubes},
          {"seconds", p.seconds},
          {"iterations", p.iterations},
          {"inner_solves", p.inner_solves},
          {"inner_iterations", p.inner_iterations}};
}

ResponsePoint point_from_json(const nlohmann::json& j) {
  ResponsePoint p;
  p.omega = j.at("omega");
  p.omega_star = j.at("omega_star");
  p.intrinsic_viscosity = {j.at("intrinsic_viscosity").at(0), j.at("intrinsic_viscosity").at(1)};
  p.cell_phi = j.at("cell_phi");
  p.cell_storage = j.at("cell_storage");
  p.cell_loss = j.at("cell_loss");
  if (!j.at("box").is_null()) p.box = cube_from_json(j.at("box"));
  p.oldroyd_intrinsic_viscosity = {j.at("oldroyd_intrinsic_viscosity").at(0),
                                   j.at("oldroyd_intrinsic_viscosity").at(1)};
  p.oldroyd_cell_storage = j.at("oldroyd_cell_storage");
  p.oldroyd_cell_loss = j.at("oldroyd_cell_loss");
  for (const auto& c : j.at("cubes")) p.cubes.push_back(cube_from_json(c));
  p.seconds = j.at("seconds");
  p.iterations = j.at("iterations");
  p.inner_solves = j.at("inner_solves");
  p.inner_iterations = j.at("inner_iterations");
  return p;
}

/// The frequencies a run of the command has solved so far, kept beside the
/// output directory (`<dir>.frequencies-done.json`, rewritten atomically
/// after each solve, removed once the results are committed), so that a run
/// stopped or killed part-way loses only the frequency it was solving: the
/// next run of the same case on the same mesh takes the kept ones and solves
/// the rest. A sweep of several frequencies on a million unknowns takes an
/// hour or more (docs/benchmarks/response.md).
class FinishedFrequencies {
 public:
  FinishedFrequencies(const fs::path& directory, std::string case_text,
                      std::vector<double> cube_sides, int unknowns)
      : path_(directory.parent_path() / (directory.filename().string() + ".frequencies-done.json")),
        key_({{"case", std::move(case_text)},
              {"cube_sides", std::move(cube_sides)},
              {"unknowns", unknowns}}) {
    // The root reads the record, every rank parses it: all hold the same points.
    std::string text;
    if (is_root() && fs::exists(path_)) {
      std::ifstream in(path_);
      text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    la::broadcast_text(text);
    if (text.empty()) return;
    try {
      const auto j = nlohmann::json::parse(text);
      if (j.at("key") != key_) {
        ignored_ = "it was made for another case, mesh or set of cubes";
        return;
      }
      for (const auto& p : j.at("points")) points_.push_back(point_from_json(p));
    } catch (const std::exception& e) {
      ignored_ = fmt::format("it cannot be read ({})", e.what());
      points_.clear();
    }
  }

  [[nodiscard]] const fs::path& path() const { return path_; }
  /// Why an existing record is not used; empty when it is (or there is none).
  [[nodiscard]] const std::string& ignored() const { return ignored_; }

  /// The kept point of `omega`, if this record has one.
  [[nodiscard]] std::optional<ResponsePoint> find(double omega) const {
    for (const auto& p : points_)
      if (p.omega == omega) return p;
    return std::nullopt;
  }

  void add(const ResponsePoint& p) {
    points_.push_back(p);
    if (!is_root()) return;
    nlohmann::json points = nlohmann::json::array();
    for (const auto& q : points_) points.push_back(point_json(q));
    io::write_text_file_atomically(
        path_, nlohmann::json{{"key", key_}, {"points", points}}.dump(1) + "\n");
  }

  /// The results are committed: nothing to resume any more.
  void forget() const {
    if (is_root()) fs::remove(path_);
  }

 private:
  fs::path path_;
  nlohmann::json key_;
  std::vector<ResponsePoint> points_;
  std::string ignored_;
};

}  // namespace

std::vector<ResponsePoint> run_frequency_response(const io::CaseConfig& config, const ResponseOptions& options) {
  const auto start = Clock::now();
  std::vector<double> frequencies = options.frequencies;
  check_response_case(config, frequencies, options.cube_sides);
  if (frequencies.empty()) frequencies = {config.flow.frequency};
  const bool root = is_root();
  const fs::path directory = options.output_directory.value_or(fs::path(config.output_directory));
  auto meshed = build_mesh(config);
  std::unique_ptr<io::OutputDirectory> output;
  on_root_sharing_failure([&] { output = std::make_unique<io::OutputDirectory>(directory, true); });
  leave_startup();  // the staging directory exists: a stop request now removes it cleanly
  const mesh::Mesh& mesh = meshed.mesh;

  physics::OscillatorySystem system(mesh, solver_settings(config).method,
                                    io::has_interface_slip(config));
  const bool iterative = system.method() == la::SaddlePointMethod::iterative;
  physics::OscillatoryProblem problem = oscillatory_problem(config, mesh);
  if (!options.quiet && root)
    fmt::print("mesh: {} nodes, {} tetrahedra, {} drops; {} real unknowns (velocity and pressure, real and "
               "imaginary parts); solver {} ({})\n",
               mesh.n_nodes(), mesh.n_tets(), mesh.n_objects, system.n_unknowns(),
               iterative ? "iterative: FGMRES with PRESB" : "direct: MUMPS LU", system.method_reason());
  const Averaging where(config, mesh, options.cube_sides);

  FinishedFrequencies finished(directory, io::to_toml(config), options.cube_sides,
                               system.n_unknowns());
  if (!options.quiet && root && !finished.ignored().empty())
    fmt::print("not resuming from {}: {}\n", finished.path().string(), finished.ignored());
  std::vector<ResponsePoint> points;
  for (double omega : frequencies) {
    if (const int signal = stop_requested())
      throw RunInterrupted(
          fmt::format("stopped by {} before the results were written; the {} frequencies solved "
                      "are kept in {}: run the "
                      "command again to solve the rest",
                      signal_name(signal), points.size(), finished.path().string()));
    if (const std::optional<ResponsePoint> kept = finished.find(omega)) {
      if (!options.quiet && root)
        fmt::print("omega {:g}: kept from an interrupted run ({})\n", omega,
                   finished.path().filename().string());
      points.push_back(*kept);
      continue;
    }
    problem.omega = omega;
    const ResponsePoint p = measure(config, mesh, system, problem, system.solve(problem), where);
    finished.add(p);
    if (!options.quiet && root)
      fmt::print("omega {:g} (omega* {:.4g}): c = {:.5f} {:+.5f} i (Oldroyd's dilute {:.5f} {:+.5f} i); cell: G' "
                 "R/Gamma {:.5g}, G''/(eta_m omega) {:.5g}; {:.1f} s{}\n",
                 omega, p.omega_star, p.intrinsic_viscosity.real(), p.intrinsic_viscosity.imag(),
                 p.oldroyd_intrinsic_viscosity.real(), p.oldroyd_intrinsic_viscosity.imag(), p.cell_storage,
                 p.cell_loss, p.seconds,
                 iterative ? fmt::format(" ({} FGMRES iterations, {} inner Stokes solves of {:.1f} iterations each)",
                                         p.iterations, p.inner_solves,
                                         p.inner_iterations / std::max(1.0, double(p.inner_solves)))
                           : std::string());
    points.push_back(p);
  }

  nlohmann::json summary = {
      {"softflow_version", SOFTFLOW_VERSION},
      {"case", config.name},
      {"command", "response"},
      {"mpi_ranks", la::mpi_size()},
      {"mesh", meshed.report},
      {"drops", mesh.n_objects},
      {"unknowns", system.n_unknowns()},
      {"solver",
       {{"method", iterative ? "iterative" : "direct"}, {"reason", system.method_reason()}}},
      {"frequencies", frequencies},
      {"cube_sides", options.cube_sides},
      {"cell_volume_fraction", points.front().cell_phi},
  };
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& p : points)
    rows.push_back({{"omega", p.omega},
                    {"omega_star", p.omega_star},
                    {"intrinsic_viscosity", {p.intrinsic_viscosity.real(), p.intrinsic_viscosity.imag()}},
                    {"cell_storage", p.cell_storage},
                    {"cell_loss", p.cell_loss},
                    {"seconds", p.seconds},
                    {"iterations", p.iterations},
                    {"inner_solves", p.inner_solves},
                    {"inner_iterations", p.inner_iterations}});
  summary["points"] = rows;
  summary["wall_seconds"] = std::chrono::duration<double>(Clock::now() - start).count();
  summary["peak_memory_mb"] = peak_memory_summary();  // collective
  on_root_sharing_failure([&] {
    output->write_text("case.toml", io::to_toml(config));
    output->write_text("response.csv", response_csv(points));
    if (!options.cube_sides.empty()) output->write_text("cubes.csv", cubes_csv(points));
    output->write_text("response.md", response_markdown(config, mesh.n_objects, system.n_unknowns(), points));
    output->write_text("summary.json", summary.dump(2) + "\n");
    output->commit();
    finished.forget();
  });
  if (root) draw_plot("plot_response.py", directory, "response.png", options.quiet);
  if (!options.quiet && root) fmt::print("wrote {}/response.md, response.csv, response.png\n", directory.string());
  return points;
}

}  // namespace softflow::simulation
