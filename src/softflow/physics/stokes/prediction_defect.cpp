#include "softflow/physics/stokes/prediction_defect.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <mpi.h>

#include "softflow/common/error.hpp"
#include "softflow/common/state.hpp"
#include "softflow/fem/dof_map.hpp"
#include "softflow/fem/field.hpp"
#include "softflow/la/petsc.hpp"
#include "softflow/mesh/mesh.hpp"
#include "softflow/physics/stokes/stokes_kernels.hpp"
#include "softflow/physics/stokes/viscoelastic_terms.hpp"
#include "softflow/physics/viscoelastic/conformation_transport.hpp"

namespace softflow::physics {

namespace ve = viscoelastic;

namespace {

/// The tetrahedra of this rank's Stokes assembly in a phase with a conformation.
std::vector<int> assembled_tets(const mesh::Mesh& mesh, const std::vector<bool>& has_conformation) {
  const auto [first, last] = fem::rank_node_range(mesh.n_nodes(), la::mpi_rank(), la::mpi_size());
  std::vector<int> tets;
  for (int t : fem::elements_touching(mesh, first, last)) {
    const auto region = static_cast<std::size_t>(mesh.tet_region[t]);
    if (region < has_conformation.size() && has_conformation[region]) tets.push_back(t);
  }
  return tets;
}

const fem::TetTabulation& stokes_rule() {
  static const fem::TetTabulation tab(kStokesQuadratureDegree);
  return tab;
}

}  // namespace

PredictionDefect::PredictionDefect(const mesh::Mesh& mesh,
                                   const std::vector<bool>& has_conformation)
    : mesh_(mesh),
      values_(mesh.n_tets(), assembled_tets(mesh, has_conformation),
              static_cast<int>(stokes_rule().p2.size())) {}

void PredictionDefect::record_prediction(const ViscoelasticCoupling& coupling,
                                         const fem::Field& velocity) {
  ViscoelasticCoupling without = coupling;
  without.defect = nullptr;
  for (int t : values_.tets())
    for (const auto& p : fem::quadrature_points(mesh_, stokes_rule(), t))
      values_.set(t, p.q,
                  predicted_conformation(without, p, velocity.value(p), velocity.gradient(p)));
  theta_dt_ = coupling.bdf.theta_dt(coupling.dt);
  measured_ = false;
}

void PredictionDefect::measure(const fem::Field& conformation) {
  for (int t : values_.tets())
    for (const auto& p : fem::quadrature_points(mesh_, stokes_rule(), t)) {
      values_.set(t, p.q, ve::unpack_symmetric(conformation.value(p)) - values_.get(t, p.q));
    }
  measured_ = true;
}

void PredictionDefect::apply(ViscoelasticCoupling& coupling) const {
  if (!measured_) return;
  coupling.defect = &values_;
  // d ~ theta dt (Pi F - F): scaled to this step's theta dt.
  coupling.defect_scale = coupling.bdf.theta_dt(coupling.dt) / theta_dt_;
}

void PredictionDefect::save(StateRecord& record, const std::string& prefix) const {
  record.set(prefix + "measured", measured_);
  record.set(prefix + "theta_dt", theta_dt_);
  if (!measured_) return;
  const int n_q = values_.points_per_tet();
  const auto n_c = static_cast<std::size_t>(ve::kSymmetricComponents);
  const bool whole = record.scope() == StateRecord::Scope::whole_run;
  // Whole run: every tetrahedron's points, each from the rank that owns it.
  const std::vector<int> tets =
      whole ? fem::owned_elements(mesh_)
            : std::vector<int>(values_.tets().begin(), values_.tets().end());
  std::vector<double> values(
      (whole ? static_cast<std::size_t>(mesh_.n_tets()) : tets.size()) * n_q * n_c, 0.0);
  for (std::size_t i = 0; i < tets.size(); ++i) {
    const int t = tets[i];
    if (!values_.holds(t)) continue;
    const std::size_t slot = whole ? static_cast<std::size_t>(t) : i;
    for (int q = 0; q < n_q; ++q) {
      const Eigen::VectorXd d = ve::pack_symmetric(values_.get(t, q));
      std::copy(d.data(), d.data() + n_c, values.begin() + (slot * n_q + q) * n_c);
    }
  }
  if (whole)
    MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM,
                  PETSC_COMM_WORLD);
  record.set(prefix + "values", std::move(values), static_cast<int>(n_q * n_c));
}

void PredictionDefect::restore(const StateRecord& record, const std::string& prefix) {
  measured_ = record.get_bool(prefix + "measured");
  theta_dt_ = record.get_double(prefix + "theta_dt");
  if (!measured_) return;
  const int n_q = values_.points_per_tet();
  const auto n_c = static_cast<std::size_t>(ve::kSymmetricComponents);
  const auto& values = record.get_array(prefix + "values", static_cast<int>(n_q * n_c));
  const bool whole = record.scope() == StateRecord::Scope::whole_run;
  const std::size_t expected =
      (whole ? static_cast<std::size_t>(mesh_.n_tets()) : values_.tets().size()) * n_q * n_c;
  if (values.size() != expected)
    throw InputError(
        fmt::format("the saved defect of the predicted conformation has {} values, {} "
                    "expected",
                    values.size(), expected));
  const auto tets = values_.tets();
  for (std::size_t i = 0; i < tets.size(); ++i) {
    const int t = tets[i];
    const std::size_t slot = whole ? static_cast<std::size_t>(t) : i;
    for (int q = 0; q < n_q; ++q) {
      const auto begin = values.begin() + static_cast<std::ptrdiff_t>((slot * n_q + q) * n_c);
      values_.set(t, q,
                  ve::unpack_symmetric(Eigen::VectorXd::Map(&*begin, ve::kSymmetricComponents)));
    }
  }
}

}  // namespace softflow::physics
