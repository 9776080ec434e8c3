#include "softflow/simulation/modules/bulk_stress_module.hpp"

#include <array>
#include <cmath>
#include <complex>

#include <fmt/format.h>

#include <mpi.h>

#include "softflow/analysis/harmonic_fit.hpp"
#include "softflow/analysis/theory/oldroyd_emulsion.hpp"
#include "softflow/element/isoparametric.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/fem/tabulation.hpp"
#include "softflow/physics/interface/interface_mesh.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/report_tables.hpp"

namespace softflow::simulation {

using Eigen::Matrix3d;
using Eigen::Vector3d;

const io::ReportTable<BulkStressRow>& bulk_stress_table() {
  using C = io::Column<BulkStressRow>;
  constexpr auto kInteger = kIntegerColumn;
  constexpr auto kFull = kStateColumn;
  const auto s = [](int i, int j) {
    return [i, j](const BulkStressRow& r) { return r.bulk.stress(i, j); };
  };
  static const io::ReportTable<BulkStressRow> table(
      "bulk_stress.csv", "step",
      "The bulk stress of eq. 4.1 over the cube of side bulk_stress.box_side centred in the cell: "
      "the volume average of sigma = -p I + 2 eta D (the matrix inside the cube, the objects "
      "whose centre of volume lies in it counted whole) plus the interfacial-tension term "
      "-Gamma/V int_S (n n - I/3) dA of those objects. Its isotropic part carries the "
      "pressure's arbitrary level; the shear stress and the normal stress differences do not. "
      "Empty (nan) at t = 0, before the first Stokes solve.",
      with_step_and_time<BulkStressRow>(std::vector<C>{
          {"sigma_xx", "stress", "<sigma>_xx", kFull, s(0, 0)},
          {"sigma_yy", "stress", "<sigma>_yy", kFull, s(1, 1)},
          {"sigma_zz", "stress", "<sigma>_zz", kFull, s(2, 2)},
          {"sigma_xy", "stress", "<sigma>_xy, the shear stress of eqs. 4.4 and 4.7", kFull, s(0, 1)},
          {"sigma_xz", "stress", "<sigma>_xz", kFull, s(0, 2)},
          {"sigma_yz", "stress", "<sigma>_yz", kFull, s(1, 2)},
          {"N1", "stress", "first normal stress difference <sigma>_xx - <sigma>_yy", kFull,
           [](const BulkStressRow& r) { return r.bulk.stress(0, 0) - r.bulk.stress(1, 1); }},
          {"N2", "stress", "second normal stress difference <sigma>_yy - <sigma>_zz", kFull,
           [](const BulkStressRow& r) { return r.bulk.stress(1, 1) - r.bulk.stress(2, 2); }},
          {"tension_xy", "stress", "the interfacial-tension term's xy component (in sigma_xy)",
           kFull, [](const BulkStressRow& r) { return r.bulk.tension(0, 1); }},
          {"slip_xy", "stress", "the slip term's xy component (in sigma_xy; 0 without slip): "
           "eta_m/V sum_i int_S [(u_d - u_m) n + n (u_d - u_m)] dA", kFull,
           [](const BulkStressRow& r) { return r.bulk.slip(0, 1); }},
          {"shear_rate", "1/time", "effective shear rate <2 D_xy> over the same volume (eq. 4.6, "
           "signed)", kFull, [](const BulkStressRow& r) { return r.bulk.shear_rate; }},
          {"viscosity", "stress time", "sigma_xy / shear_rate: the suspension's shear viscosity "
           "in steady shear", kFull,
           [](const BulkStressRow& r) { return r.bulk.stress(0, 1) / r.bulk.shear_rate; }},
          {"stresslet_xy", "stress volume", "V (sigma_xy - eta_m shear_rate): the counted objects' "
           "stresslets S_xy summed, independent of the cube for objects wholly inside it "
           "(docs/emulsions.md)", kFull, [](const BulkStressRow& r) { return r.bulk.stresslet_xy; }},
          {"phi", "", "volume fraction: the counted objects' volume over the cube's", kFull,
           [](const BulkStressRow& r) { return r.bulk.volume_fraction; }},
          {"objects", "", "objects whose centre of volume lies in the cube", kInteger,
           [](const BulkStressRow& r) { return r.bulk.objects_counted; }}}));
  return table;
}

BulkStressModule::BulkStressModule(const ModuleSetup& setup)
    : mesh_(setup.mesh),
      stokes_(setup.stokes),
      box_(analysis::centred_cube(setup.config.bulk_stress.box_side)),
      velocity_(setup.mesh, "bulk_stress_velocity",
                setup.stokes.dofs().field(physics::kVelocityField).space, 3),
      pressure_(setup.mesh, "bulk_stress_pressure",
                setup.stokes.dofs().field(physics::kPressureField).space, 1),
      config_(setup.config) {
  // Newtonian phases (io::parse_case refuses the others): mu is eta.
  for (const auto& m : setup.models) viscosities_.push_back(m.solvent_viscosity());
  for (const auto& o : setup.config.objects) {
    tensions_.push_back(o.interfacial_tension);
    slips_.push_back(o.slip != 0.0);
  }
}

bool BulkStressModule::wanted(const ModuleSetup& setup) {
  return setup.config.bulk_stress.box_side > 0.0;
}

namespace {

/// int_S (n n - I/3) dA over a curved P2 interface at positions x.
Matrix3d normal_moment(const physics::InterfaceMesh& s, const std::vector<Vector3d>& x) {
  static const element::QuadratureRule rule = element::triangle_rule(4);
  Matrix3d m = Matrix3d::Zero();
  for (const auto& tri : s.triangles) {
    element::TriangleNodes nodes;
    for (int k = 0; k < 6; ++k) nodes.col(k) = x[tri[k]];
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(nodes, rule.points[q]);
      m += rule.weights[q] * p.area_scale * (p.normal * p.normal.transpose() - Matrix3d::Identity() / 3.0);
    }
  }
  return m;
}

/// int_S [(u_d - u_m) n + n (u_d - u_m)] dA over a curved P2 interface at
/// positions x (eq. 4.1's slip term over eta_m), n out of the object, the
/// two velocity copies of each interface node read through `value(dof)`.
Matrix3d slip_moment(const physics::InterfaceMesh& s, const std::vector<Vector3d>& x,
                     const fem::DofMap& dofs, const la::SelectedEntries& values) {
  static const element::QuadratureRule rule = element::triangle_rule(4);
  Matrix3d m = Matrix3d::Zero();
  for (const auto& tri : s.triangles) {
    element::TriangleNodes nodes;
    Eigen::Matrix<double, 3, 6> jump;  // u_d - u_m at the six nodes
    for (int k = 0; k < 6; ++k) {
      nodes.col(k) = x[tri[k]];
      const int node = s.volume_node[tri[k]];
      for (int c = 0; c < 3; ++c)
        jump(c, k) = values[dofs.dof(physics::kVelocityField, node, s.object, c)] -
                     values[dofs.dof(physics::kVelocityField, node, 0, c)];
    }
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(nodes, rule.points[q]);
      const auto n = element::p2_triangle_values(rule.points[q]);
      const Vector3d du = jump * Eigen::Map<const Eigen::Matrix<double, 6, 1>>(n.data());
      const Matrix3d outer = du * p.normal.transpose();
      m += rule.weights[q] * p.area_scale * (outer + outer.transpose());
    }
  }
  return m;
}

}  // namespace

void BulkStressModule::integrate_volume(const std::vector<bool>& counted, Matrix3d& stress,
                                        double& shear_rate, double& volume) const {
  static const element::QuadratureRule rule = element::tetrahedron_rule(2);
  stress.setZero();
  shear_rate = 0.0;
  volume = 0.0;
  for (int t : velocity_.owned_elements()) {
    const int region = mesh_.tet_region[t];
    if (region > 0 && !counted[region]) continue;
    const element::TetNodes nodes = fem::tet_nodes(mesh_, t);
    // The pieces of the element to integrate over, in reference coordinates.
    const std::vector<analysis::Tetrahedron> pieces =
        region > 0 ? std::vector<analysis::Tetrahedron>{analysis::reference_tetrahedron()}
                   : analysis::reference_pieces_in_box(nodes, box_);
    if (pieces.empty()) continue;
    const Eigen::VectorXd u = velocity_.element_coefficients(t);
    const Eigen::VectorXd p = pressure_.element_coefficients(t);
    const double eta = viscosities_.at(region);
    analysis::for_each_point_in_pieces(nodes, pieces, rule, [&](const Vector3d& xi, double w, const auto& grad) {
      Matrix3d l = Matrix3d::Zero();  // l(i, j) = du_i / dx_j
      for (int k = 0; k < 10; ++k) l += u.segment<3>(3 * k) * grad.row(k);
      const auto psi = element::p1_tet_values(xi);
      double pressure = 0.0;
      for (int k = 0; k < 4; ++k) pressure += psi[k] * p(k);
      stress += w * (-pressure * Matrix3d::Identity() + eta * (l + l.transpose()));
      shear_rate += w * (l(0, 1) + l(1, 0));
      volume += w;
    });
  }
}

void BulkStressModule::measure(const StepContext& context, StepReport& /*report*/) {
  last_ = BulkStress{};
  last_.box_volume = box_.volume();
  // The objects counted: centre of volume of the interface the flow was solved on.
  std::vector<bool> counted(mesh_.n_objects + 1, false);
  Matrix3d tension = Matrix3d::Zero(), slip = Matrix3d::Zero();
  double counted_volume = 0.0;
  for (std::size_t k = 0; k < context.interfaces.size(); ++k) {
    const auto& surface = context.interfaces[k].surface();
    const auto x = physics::interface_positions(surface, mesh_);
    const auto integrals = physics::surface_integrals(surface, x);
    if (!box_.contains(integrals.centre_of_volume())) continue;
    counted[surface.object] = true;
    counted_volume += integrals.volume;
    ++last_.objects_counted;
    tension -= tensions_.at(k) * normal_moment(surface, x);  // eq. 4.1, second term
    // eq. 4.1, third term: with it, <sigma> - eta_m <2 D> (2 D averaged in each
    // phase, the jump at the interface left out as eq. 4.6 leaves it out) is the
    // objects' stresslet (docs/emulsions.md).
    if (slips_.at(k) && context.interface_values != nullptr)
      slip += viscosities_[0] * slip_moment(surface, x, stokes_.dofs(), *context.interface_values);
  }
  last_.volume_fraction = counted_volume / last_.box_volume;
  last_.tension = tension / last_.box_volume;
  if (context.solution == nullptr) return;  // no flow yet

  velocity_.assign_from(stokes_.dofs(), physics::kVelocityField, context.solution);
  pressure_.assign_from(stokes_.dofs(), physics::kPressureField, context.solution);
  Matrix3d stress;
  double shear_rate = 0.0, volume = 0.0;
  integrate_volume(counted, stress, shear_rate, volume);
  std::array<double, 11> sums{};
  for (int i = 0; i < 9; ++i) sums[i] = stress(i / 3, i % 3);
  sums[9] = shear_rate;
  sums[10] = volume;
  MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM,
                PETSC_COMM_WORLD);
  for (int i = 0; i < 9; ++i) stress(i / 3, i % 3) = sums[i];
  last_.stress = (stress + tension + slip) / last_.box_volume;
  last_.slip = slip / last_.box_volume;
  last_.shear_rate = sums[9] / last_.box_volume;
  last_.stresslet_xy = last_.box_volume * (last_.stress(0, 1) - viscosities_[0] * last_.shear_rate);

  // A time measured again (after a restart, or a step taken back and retried)
  // replaces what was recorded from it on.
  const double t = context.time;
  while (!history_.empty() && history_.back().t >= t) history_.pop_back();
  history_.push_back({t, last_.stress(0, 1), last_.shear_rate, last_.stresslet_xy, counted_volume});
}

std::vector<StatePart> BulkStressModule::state_parts() {
  constexpr int kColumns = 5;
  auto save = [this](StateRecord& r, const std::string& p) {
    std::vector<double> values;
    values.reserve(kColumns * history_.size());
    for (const auto& h : history_)
      values.insert(values.end(), {h.t, h.stress_xy, h.shear_rate, h.stresslet_xy, h.counted_volume});
    r.set(p + "history", std::move(values), kColumns);
  };
  auto restore = [this](const StateRecord& r, const std::string& p) {
    history_.clear();
    const auto& values = r.get_array(p + "history", kColumns);
    for (std::size_t i = 0; i + kColumns <= values.size(); i += kColumns)
      history_.push_back({values[i], values[i + 1], values[i + 2], values[i + 3], values[i + 4]});
  };
  return {{"bulk_stress", save, restore}};
}

void BulkStressModule::carry_over(StepModule& old, const fem::MeshTransfer& /*transfer*/) {
  history_ = dynamic_cast<const BulkStressModule&>(old).history_;
}

std::vector<ReportFile> BulkStressModule::report_files() const {
  return {{bulk_stress_table().file(), bulk_stress_table().header(),
           [this](const StepReport& report) { return bulk_stress_table().row({report, last_}); }}};
}

void BulkStressModule::summarise(nlohmann::json& summary) const {
  const StepReport none;
  summary["final_bulk_stress"] = bulk_stress_table().json_row({none, last_}, {"step", "t"});
  if (config_.flow.type == io::FlowType::oscillatory)
    summary["moduli"] = oscillatory_moduli(history_, config_, box_.volume());
}

nlohmann::json oscillatory_moduli(std::span<const BulkStressSample> history, const io::CaseConfig& config,
                                  double box_volume) {
  const double omega = config.flow.frequency, periods = config.bulk_stress.fit_periods;
  std::vector<double> t;
  for (const auto& h : history) t.push_back(h.t);
  const std::size_t first = analysis::last_periods_start(t, omega, periods);
  nlohmann::json moduli;
  moduli["frequency"] = omega;
  moduli["periods_fitted"] = periods;
  if (history.size() - first < 4) {  // first == history.size(): too few periods recorded
    const double run = t.empty() ? 0.0 : (t.back() - t.front()) * omega / (2.0 * M_PI);
    moduli["note"] = fmt::format(
        "not fitted: {:.3g} periods of oscillatory flow recorded, bulk_stress.fit_periods = {:g} "
        "needed (a longer time.end or more flow.periods)",
        run, periods);
    return moduli;
  }
  const auto window = history.subspan(first);
  const auto column = [&](double BulkStressSample::*member) {
    std::vector<double> v;
    for (const auto& h : window) v.push_back(h.*member);
    return v;
  };
  const auto times = column(&BulkStressSample::t);
  const auto stress = analysis::fit_harmonic(times, column(&BulkStressSample::stress_xy), omega);
  const auto rate = analysis::fit_harmonic(times, column(&BulkStressSample::shear_rate), omega);
  const auto stresslet = analysis::fit_harmonic(times, column(&BulkStressSample::stresslet_xy), omega);
  const std::complex<double> g = analysis::complex_modulus(stress.amplitude, rate.amplitude, omega);
  // The walls' shear rate gamma0 omega sin(omega t) = Re(-i gamma0 omega e^{i omega t}).
  const std::complex<double> wall_rate(0.0, -config.flow.strain_amplitude * omega);
  double volume = 0.0;
  for (const auto& h : window) volume += h.counted_volume;
  volume /= static_cast<double>(window.size());
  const double eta_m = config.matrix_viscosity, phi = volume / box_volume;

  moduli["from_t"] = times.front();
  moduli["to_t"] = times.back();
  moduli["samples"] = times.size();
  moduli["G_storage"] = g.real();
  moduli["G_loss"] = g.imag();
  moduli["G_loss_over_eta_m_omega"] = g.imag() / (eta_m * omega);
  moduli["shear_rate_amplitude"] = std::abs(rate.amplitude);
  moduli["shear_rate_phase_vs_wall"] = std::arg(rate.amplitude / wall_rate);
  moduli["fit_residual_stress"] = stress.residual;
  moduli["fit_residual_shear_rate"] = rate.residual;
  moduli["volume_fraction"] = phi;
  if (config.objects.empty() || volume == 0.0) return moduli;

  // Drops: G' in units of Gamma / R, and Oldroyd's emulsion beside the run (objects[1]'s R, Gamma, lambda).
  const io::ObjectConfig& drop = config.objects.front();
  const double radius = io::mean_radius(drop.geometry), tension = drop.interfacial_tension;
  const std::complex<double> intrinsic = stresslet.amplitude / (eta_m * volume * wall_rate);
  moduli["stresslet_coefficient"] = {intrinsic.real(), intrinsic.imag()};
  moduli["fit_residual_stresslet"] = stresslet.residual;
  if (tension > 0.0 && drop.model == physics::viscoelastic::ConstitutiveModel::newtonian) {
    const double tau_em = eta_m * radius / tension, omega_star = omega * tau_em;
    moduli["omega_star"] = omega_star;
    moduli["G_storage_R_over_Gamma"] = g.real() * radius / tension;
    const auto theory = analysis::theory::oldroyd_moduli(drop.viscosity_ratio, phi, omega_star, drop.slip);
    const auto dilute = analysis::theory::oldroyd_dilute_coefficient(drop.viscosity_ratio, omega_star, drop.slip);
    moduli["oldroyd"] = {{"G_storage_R_over_Gamma", theory.storage},
                         {"G_loss_over_eta_m_omega", theory.loss},
                         {"dilute_coefficient", {dilute.real(), dilute.imag()}}};
  }
  return moduli;
}

}  // namespace softflow::simulation
