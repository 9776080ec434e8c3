#include "softflow/simulation/viscoelastic_phases.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>
#include <mpi.h>

#include "softflow/fem/mesh_transfer.hpp"
#include "softflow/la/petsc.hpp"
#include "softflow/simulation/step_module.hpp"
#include "softflow/common/error.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/physics/viscoelastic/constitutive_law.hpp"
#include "softflow/physics/viscoelastic/conformation_transport.hpp"

namespace softflow::simulation {

namespace ve = physics::viscoelastic;
using la::check;

namespace {

/// Applies f to the owned values of `field`, node block by node block
/// (components contiguous), with the block's first dof; then updates ghosts.
template <class F>
void for_each_owned_block(fem::Field& field, F&& f) {
  PetscScalar* a = nullptr;
  check(VecGetArray(field.vector(), &a), "VecGetArray");
  const auto range = field.ownership();
  const int n_c = field.components();
  for (int dof = range.begin; dof < range.end; dof += n_c)
    f(dof, Eigen::Map<Eigen::VectorXd>(a + (dof - range.begin), n_c));
  check(VecRestoreArray(field.vector(), &a), "VecRestoreArray");
  field.update_ghosts();
}

}  // namespace

ViscoelasticPhases::ViscoelasticPhases(const mesh::Mesh& mesh, std::vector<ve::Constitutive> models,
                                       bool slip_velocity, std::vector<physics::SupgTau> supg_taus,
                                       physics::viscoelastic::StressPrediction prediction,
                                       bool devss_g)
    : mesh_(mesh),
      models_(std::move(models)),
      p1_(std::make_shared<fem::Space>(mesh, 1, fem::Continuity::per_region)),
      p2_(std::make_shared<fem::Space>(mesh, 2, fem::Continuity::continuous)),
      velocity_space_(
          slip_velocity ? std::make_shared<fem::Space>(mesh, 2, fem::Continuity::per_region) : p2_),
      log_conformation_(mesh, "log_conformation", p1_, ve::kSymmetricComponents),
      conformation_(mesh, "conformation", p1_, ve::kSymmetricComponents),
      stress_(mesh, "polymer_stress", p1_, ve::kSymmetricComponents),
      previous_conformation_(mesh, "previous_conformation", p1_, ve::kSymmetricComponents),
      velocity_(mesh, "velocity", velocity_space_, 3),
      mesh_velocity_(mesh, "mesh_velocity", p2_, 3),
      gradient_(mesh, "velocity_gradient", p1_, physics::kVelocityGradientComponents) {
  if (static_cast<int>(models_.size()) != mesh.n_objects + 1)
    throw Error(fmt::format("ViscoelasticPhases: {} models for {} regions", models_.size(),
                            mesh.n_objects + 1));
  // c = I everywhere at t = 0 (eq. 2.20): s = 0, tau = 0.
  for_each_owned_block(conformation_, [](int, auto c) { c = ve::pack_symmetric(ve::Mat3::Identity()); });
  supg_taus_ = supg_taus;
  devss_g_ = devss_g;
  transport_ = std::make_unique<physics::AleTransport>(log_conformation_, std::move(supg_taus));
  source_ = ve::log_conformation_source(models_, velocity_, log_conformation_, *transport_);
  prediction_ = prediction;
  if (prediction == physics::viscoelastic::StressPrediction::consistent) {
    std::vector<bool> has_conformation;
    for (const auto& m : models_) has_conformation.push_back(m.has_conformation());
    defect_.emplace(mesh, has_conformation);
  }
}

ViscoelasticPhases::~ViscoelasticPhases() = default;

bool ViscoelasticPhases::needed(const std::vector<ve::Constitutive>& models) {
  return std::any_of(models.begin(), models.end(),
                     [](const ve::Constitutive& m) { return m.has_conformation(); });
}

physics::ViscoelasticCoupling ViscoelasticPhases::coupling(
    std::span<const mesh::Point> mesh_velocity, double dt) {
  // The mesh velocity per geometry node, as a P2 field (every rank holds
  // all nodes today; issue 12 makes this rank-local).
  std::vector<double> all(mesh_velocity_.dofs().n_dofs(), 0.0);
  for (int node = 0; node < mesh_.n_nodes(); ++node)
    for (int c = 0; c < 3; ++c) all[mesh_velocity_.dofs().dof(0, node, 0, c)] = mesh_velocity[node](c);
  mesh_velocity_.scatter(all);

  physics::ViscoelasticCoupling coupling;
  coupling.models = models_;
  coupling.conformation = &conformation_;
  if (prediction_ == physics::viscoelastic::StressPrediction::consistent) {
    coupling.bdf = transport_->next_bdf(dt);
    coupling.extrapolation = transport_->next_extrapolation(dt);
    if (coupling.bdf.a2 != 0.0 || coupling.extrapolation.previous != 0.0) {
      update_previous_conformation();
      coupling.previous_conformation = &previous_conformation_;
    }
  }
  coupling.mesh_velocity = &mesh_velocity_;
  coupling.velocity_gradient = devss_g_ && gradient_steps_ > 0 ? &gradient_ : nullptr;
  coupling.dt = dt;
  if (defect_) defect_->apply(coupling);
  last_coupling_ = coupling;
  return coupling;
}

void ViscoelasticPhases::advance(const fem::DofMap& stokes_dofs, Vec solution,
                                 double dt, double t_new, int step) {
  velocity_.assign_from(stokes_dofs, physics::kVelocityField, solution);
  // s_n too: a restored state may carry what a run never would, and the
  // source's eigen-decomposition would otherwise fail without saying where.
  check_finite(t_new, step);
  if (defect_) defect_->record_prediction(last_coupling_, velocity_);
  transport_->step(velocity_, &mesh_velocity_, source_, dt, t_new);
  check_finite(t_new, step);
  update_conformation_and_stress(t_new, step);
  if (defect_) defect_->measure(conformation_);
  update_velocity_gradient();
}

void ViscoelasticPhases::restart_time_history() {
  transport_->restart_history();
  gradient_steps_ = 0;
  if (defect_) defect_->reset();  // not smooth across the jump
}

void ViscoelasticPhases::update_previous_conformation() {
  // c_{n-1} = exp(s_{n-1}) node by node, as conformation_ was one step ago,
  // from the transport's history (which restarts and remeshes keep).
  exponentiate(transport_->previous(), previous_conformation_);
}

void ViscoelasticPhases::exponentiate(const fem::Field& s_field, fem::Field& c_field) const {
  PetscScalar* c = nullptr;
  const PetscScalar* s = nullptr;
  check(VecGetArrayRead(s_field.vector(), &s), "VecGetArrayRead");
  check(VecGetArray(c_field.vector(), &c), "VecGetArray");
  const auto& dofs = c_field.dofs();
  const auto range = c_field.ownership();
  for (int dof = range.begin; dof < range.end; dof += ve::kSymmetricComponents) {
    const int i = dof - range.begin;
    const ve::Mat3 c_node =
        models_.at(dofs.region_of(dof)).has_conformation()
            ? ve::matrix_exp(ve::unpack_symmetric(
                  Eigen::Map<const Eigen::VectorXd>(s + i, ve::kSymmetricComponents)))
            : ve::Mat3::Identity();
    Eigen::Map<Eigen::VectorXd>(c + i, ve::kSymmetricComponents) = ve::pack_symmetric(c_node);
  }
  check(VecRestoreArrayRead(s_field.vector(), &s), "VecRestoreArrayRead");
  check(VecRestoreArray(c_field.vector(), &c), "VecRestoreArray");
  c_field.update_ghosts();
}

void ViscoelasticPhases::carry_over(ViscoelasticPhases& old, const fem::MeshTransfer& transfer) {
  std::array<fem::Field*, 4> to{&log_conformation_, &conformation_, &stress_, &gradient_};
  std::array<fem::Field*, 4> from{&old.log_conformation_, &old.conformation_, &old.stress_, &old.gradient_};
  carry_fields_over(to, from, transfer);
  transport_->carry_over(*old.transport_, transfer);
  gradient_steps_ = old.gradient_steps_;
  if (defect_ && old.defect_ && old.defect_->measured()) estimate_defect(old, transfer);
}

void ViscoelasticPhases::estimate_defect(const ViscoelasticPhases& old,
                                         const fem::MeshTransfer& transfer) {
  // The defect lives at the old mesh's quadrature points. Measure it afresh
  // here by taking the last step again, dry: from c_{n-1} with u_n and the
  // mesh velocity u_m of that step, as a BDF1 step (c_{n-2} is not kept):
  // d ~ theta dt (Pi F - F) differs from the uninterrupted run's by O(dt^2),
  // as from one step to the next. Without it the first step after a remesh
  // takes no defect. Measured on tests/verification/test_remesh_run.cpp's
  // particle: D 7.4e-5 off the never-remeshed run's with it, 1.4e-4
  // without; <tau_xy> 2.34e-3 and 2.40e-3 (that gap is the new mesh's).
  const double dt = old.transport_->last_step();
  if (!(dt > 0.0)) return;
  velocity_.scatter(
      transfer.transfer(old.velocity_.space(), velocity_.space(), 3, old.velocity_.gather()));
  mesh_velocity_.scatter(transfer.transfer(old.mesh_velocity_.space(), mesh_velocity_.space(), 3,
                                           old.mesh_velocity_.gather()));
  update_previous_conformation();  // c_{n-1}, the dry step's start
  physics::ViscoelasticCoupling coupling;
  coupling.models = models_;
  coupling.conformation = &previous_conformation_;
  coupling.mesh_velocity = &mesh_velocity_;
  coupling.dt = dt;  // bdf and extrapolation: BDF1's, the defaults
  defect_->record_prediction(coupling, velocity_);

  fem::Field s(mesh_, "log_conformation_dry_step", p1_, ve::kSymmetricComponents);
  check(VecCopy(transport_->previous().vector(), s.vector()), "VecCopy");
  s.update_ghosts();
  physics::AleTransport dry(s, supg_taus_);
  const auto source = ve::log_conformation_source(models_, velocity_, s, dry);
  dry.step(velocity_, &mesh_velocity_, source, dt, 0.0);
  fem::Field c(mesh_, "conformation_dry_step", p1_, ve::kSymmetricComponents);
  exponentiate(s, c);
  defect_->measure(c);
}

void ViscoelasticPhases::check_finite(double t_new, int step) {
  // s must be finite; c = exp(s) is then positive definite by construction.
  int bad = -1;
  for_each_owned_block(log_conformation_, [&](int dof, auto s) {
    if (bad < 0 && !s.allFinite()) bad = dof;
  });
  int any_bad = bad;
  MPI_Allreduce(&bad, &any_bad, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  if (any_bad >= 0) {
    const int region = log_conformation_.dofs().region_of(any_bad);
    throw SolverError(fmt::format(
        "step {} (t = {:.4f}): the log-conformation tensor is not finite at {} ({} phase). The "
        "conformation equation was not resolved there: try a smaller time.step or a finer mesh "
        "(more mesh.equator_nodes)",
        step, t_new, place(any_bad), ve::to_string(models_.at(region).model())));
  }
}

std::string ViscoelasticPhases::place(int dof) const {
  const auto& dofs = log_conformation_.dofs();
  const int node = dofs.node_of(dof), region = dofs.region_of(dof);
  const auto& x = mesh_.nodes[node];
  return fmt::format("node {} {}, near ({:.3f}, {:.3f}, {:.3f})", node,
                     region == 0 ? std::string("in the matrix") : fmt::format("in object {}", region),
                     x.x(), x.y(), x.z());
}

void ViscoelasticPhases::update_conformation_and_stress(double t_new, int step) {
  exponentiate(log_conformation_, conformation_);
  const auto& dofs = conformation_.dofs();
  int bad = -1;  // the first dof whose c the model does not admit (FENE-P: tr c >= L^2)
  std::string why;
  const PetscScalar* c = nullptr;
  PetscScalar* tau = nullptr;
  check(VecGetArrayRead(conformation_.vector(), &c), "VecGetArrayRead");
  check(VecGetArray(stress_.vector(), &tau), "VecGetArray");
  const auto range = conformation_.ownership();
  for (int dof = range.begin; dof < range.end; dof += ve::kSymmetricComponents) {
    const int i = dof - range.begin;
    const auto& model = models_.at(dofs.region_of(dof));
    const ve::Mat3 cn =
        ve::unpack_symmetric(Eigen::Map<const Eigen::VectorXd>(c + i, ve::kSymmetricComponents));
    auto stress = Eigen::Map<Eigen::VectorXd>(tau + i, ve::kSymmetricComponents);
    if (auto reason = model.law().inadmissible(cn); reason.empty()) {
      stress = ve::pack_symmetric(ve::polymer_stress(model, cn));
    } else {
      stress.setConstant(std::nan(""));
      if (bad < 0) {
        bad = dof;
        why = std::move(reason);
      }
    }
  }
  check(VecRestoreArrayRead(conformation_.vector(), &c), "VecRestoreArrayRead");
  check(VecRestoreArray(stress_.vector(), &tau), "VecRestoreArray");
  // The log-conformation keeps c positive definite, not inside every
  // model's domain: stop where the step left it, naming the place.
  int any_bad = bad;
  MPI_Allreduce(&bad, &any_bad, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  if (any_bad >= 0) {
    // The reason, from the rank that found it.
    int rank = 0, owner = -1;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    const int mine = any_bad == bad ? rank : -1;
    MPI_Allreduce(&mine, &owner, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
    la::broadcast_text(why, owner);
    throw SolverError(fmt::format(
        "step {} (t = {:.4f}): the conformation left the domain of the {} model at {}: {}. The "
        "conformation equation was not resolved there: try a smaller time.step or a finer mesh "
        "(more mesh.equator_nodes)",
        step, t_new, ve::to_string(models_.at(dofs.region_of(any_bad)).model()), place(any_bad),
        why));
  }
  stress_.update_ghosts();
}

void ViscoelasticPhases::update_velocity_gradient() {
  // G_n = P1 projection of grad u_n per region (eq. 2.36 with u given),
  // the DEVSS-G gradient of the next Stokes step (physics/stokes/viscoelastic_terms.hpp
  // explains why G_n and not an extrapolation).
  fem::l2_project(
      [this](const fem::QuadraturePoint& p) {
        const Eigen::MatrixXd l = velocity_.gradient(p);  // row i = grad u_i
        Eigen::VectorXd g(9);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) g(3 * i + j) = l(i, j);
        return g;
      },
      gradient_);
  ++gradient_steps_;
}

RegionStress ViscoelasticPhases::region_stress(int region) const {
  static const fem::TetTabulation tab(2);
  // Two passes over this rank's elements of the region: the volume and
  // int tau, then int |tau - <tau>|^2 (a one-pass <|tau|^2> - |<tau>|^2
  // would lose the spread of a nearly uniform stress to cancellation).
  auto integrate = [&](const auto& integrand, double* sums, int n) {
    std::vector<double> local(n, 0.0);
    for (int t : stress_.owned_elements()) {
      if (mesh_.tet_region[t] != region) continue;
      for (const auto& p : fem::quadrature_points(mesh_, tab, t))
        integrand(p.weight, ve::unpack_symmetric(stress_.value(p)), local.data());
    }
    MPI_Allreduce(local.data(), sums, n, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
  };
  double first[7];
  integrate(
      [](double w, const ve::Mat3& tau, double* acc) {
        acc[0] += w;
        const Eigen::VectorXd packed = ve::pack_symmetric(tau);
        for (int i = 0; i < 6; ++i) acc[1 + i] += w * packed(i);
      },
      first, 7);
  RegionStress r;
  r.region = region;
  r.volume = first[0];
  if (first[0] <= 0.0) return r;
  Eigen::VectorXd mean(6);
  for (int i = 0; i < 6; ++i) mean(i) = first[1 + i] / first[0];
  r.mean = ve::unpack_symmetric(mean);
  double deviation = 0.0;
  integrate([&r](double w, const ve::Mat3& tau,
                 double* acc) { acc[0] += w * (tau - r.mean).squaredNorm(); },
            &deviation, 1);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(r.mean);
  r.principal = eigen.eigenvalues().reverse();
  const double norm2 = r.mean.squaredNorm();
  r.spread = norm2 > 0.0 ? std::sqrt(deviation / first[0] / norm2) : 0.0;
  return r;
}

std::vector<fem::Field*> ViscoelasticPhases::output_fields() {
  return {&log_conformation_, &conformation_, &stress_};
}

StatePart ViscoelasticPhases::state_part() {
  auto save = [this](StateRecord& r, const std::string& p) {
    transport_->state_part().save(r, p + "transport/");
    gradient_.save(r, p + "velocity_gradient", gradient_.components());
    r.set(p + "gradient_steps", gradient_steps_);
    if (defect_) defect_->save(r, p + "prediction_defect/");
  };
  auto restore = [this](const StateRecord& r, const std::string& p) {
    transport_->state_part().restore(r, p + "transport/");
    gradient_.restore(r, p + "velocity_gradient", gradient_.components());
    gradient_steps_ = r.get_int(p + "gradient_steps");
    if (defect_) defect_->restore(r, p + "prediction_defect/");
  };
  return {"viscoelastic", save, restore};
}

}  // namespace softflow::simulation
