#include "softflow/physics/stokes/stokes_system.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/common/state.hpp"
#include "softflow/fem/field.hpp"
#include "softflow/la/vector_values.hpp"
#include "softflow/physics/stokes/interface_slip.hpp"
#include "softflow/physics/stokes/schur_estimate.hpp"
#include "softflow/physics/stokes/stokes_kernels.hpp"
#include "softflow/physics/stokes/viscoelastic_terms.hpp"
#include "softflow/time/bdf.hpp"

namespace softflow::physics {

namespace {
using la::check;

/// The viscosity region r's Schur-complement estimate M/eta divides by
/// (what assemble hands add_stokes_tet_matrix as pressure_mass_viscosity):
/// a viscoelastic phase's step viscosity, else the Newtonian one.
double pressure_mass_viscosity(const StokesProblem& problem, int region) {
  const auto& viscoelastic = problem.viscoelastic;
  if (viscoelastic.active() && viscoelastic.models.at(region).has_conformation())
    return viscoelastic.step_viscosity(region);
  return problem.viscosity.at(region);
}
}  // namespace

fem::DofMap make_stokes_dof_map(const mesh::Mesh& mesh, bool interface_slip) {
  using fem::Continuity;
  auto velocity = std::make_shared<fem::Space>(
      mesh, 2, interface_slip ? Continuity::per_region : Continuity::continuous);
  auto pressure = std::make_shared<fem::Space>(mesh, 1, Continuity::per_region);
  std::vector<fem::FieldSpec> fields{{"velocity", velocity, 3}, {"pressure", pressure, 1}};
  if (interface_slip)
    fields.push_back(
        {"multiplier", std::make_shared<fem::Space>(mesh, 2, Continuity::on_interfaces), 3});
  return fem::DofMap(mesh, std::move(fields));
}

StokesSystem::StokesSystem(const mesh::Mesh& mesh, const la::SaddlePointSettings& settings,
                           bool interface_slip)
    : mesh_(mesh),
      settings_(settings),
      slip_(interface_slip),
      dofs_(make_stokes_dof_map(mesh, interface_slip)),
      tabulation_(kStokesQuadratureDegree) {
  // Stale LU factors precondition a slip system worse: its constraint rows
  // carry the nodal normals, which turn with the deforming drop, and
  // alpha (I - nn) lambda then mixes the large normal traction (the Laplace
  // pressure) into the tangential law. Measured (unit drop, lambda 1,
  // Ca 0.1, alpha 1, N 28, 40 steps of 0.02): refactoring after 25
  // iterations gives 19.8 iterations per step and 0.63 s of solve per
  // step; after 8, 5.7 iterations, 4 factorisations and 0.30 s (one
  // factorisation costs about 42 iterations here). No-slip runs keep the
  // default, measured best for them (PLATFORM.md).
  if (slip_) {
    settings_.max_reuse_iterations = std::min(settings_.max_reuse_iterations, 8);
    for (int k = 1; k <= mesh_.n_objects; ++k) surfaces_.push_back(extract_interface(mesh_, k));
  }
  // The element kernels are written for the Taylor-Hood element.
  if (dofs_.element_size() != TetMatrix::RowsAtCompileTime)
    throw SolverError(fmt::format("StokesSystem: {} element dofs, the kernels take {}",
                                  dofs_.element_size(), TetMatrix::RowsAtCompileTime));
  // Before create_matrices, which lays the matrices out for the method.
  la::MethodChoice choice = la::choose_method(settings_.method, dofs_.n_dofs(), settings_.planned_steps,
                                           settings_.relaxing_phase);
  settings_.method = choice.method;
  method_reason_ = std::move(choice.reason);
  partition();
  create_matrices();
  if (gauge_after_solve()) attach_pressure_nullspace();
  // The iterative method splits velocity from the constraints: pressure,
  // and with slip the multipliers too (one Schur complement, see
  // assemble_slip_schur_estimate).
  std::vector<la::NamedIndexSet> fields;
  for (int f = 0; f < dofs_.n_fields(); ++f)
    fields.push_back({dofs_.field(f).name, field_index_sets_[f].get()});
  if (slip_) {
    std::vector<PetscInt> constraints;
    for (PetscInt i = range_.begin; i < range_.end; ++i)
      if (dofs_.field_of(static_cast<int>(i)) != kVelocityField) constraints.push_back(i);
    field_index_sets_.push_back(la::make_index_set(constraints));
    fields = {fields[kVelocityField], {"pressure_multiplier", field_index_sets_.back().get()}};
  }
  const auto near_nullspace = velocity_near_nullspace();
  solver_ = std::make_unique<la::SaddlePointSolver>(settings_, fields, near_nullspace.get());
}

void StokesSystem::update_coarse_spaces(const StokesProblem& problem) {
  const double eta_matrix = pressure_mass_viscosity(problem, 0);
  auto& schur = solver_->schur_correction();
  if (!coarse_spaces_made_) {
    // The objects less viscous than the matrix: their constant pressure.
    // Those more viscous: their rigid motions, on the geometry of each
    // build of the preconditioner (so a kept one keeps the vectors it was
    // built with, and a restart rebuilds the same).
    std::vector<int> stiff;
    for (int k = 1; k <= mesh_.n_objects; ++k) {
      const double eta = pressure_mass_viscosity(problem, k);
      if (eta < eta_matrix) {
        schur.vectors.push_back(object_pressure_constant(k));
        schur.coefficients.push_back(0.0);
        schur_correction_objects_.push_back(k);
      } else if (eta > eta_matrix) {
        stiff.push_back(k);
      }
    }
    if (!stiff.empty())
      solver_->set_primal_coarse_space([this, stiff](std::vector<la::SparseVector>& space) {
        space = rigid_motions(*assembled_geometry_, stiff);
      });
    coarse_spaces_made_ = true;
  }
  if (!schur.empty()) {
    la::Vector product;
    check(VecDuplicate(schur.vectors.front().get(), product.out()), "VecDuplicate");
    for (std::size_t i = 0; i < schur.vectors.size(); ++i) {
      const int k = schur_correction_objects_[i];
      const double eta = pressure_mass_viscosity(problem, k);
      // z^T (-f M / eta) z = -f V / eta: the object's volume from the matrix.
      PetscScalar zmz = 0.0;
      check(MatMult(schur_->get(), schur.vectors[i].get(), product.get()), "MatMult");
      check(VecDot(product.get(), schur.vectors[i].get(), &zmz), "VecDot");
      const double volume = -zmz * eta / pressure_mass_weight(eta / eta_matrix);
      schur.coefficients[i] = constant_pressure_correction(eta, eta_matrix, volume);
    }
  }
}

la::Vector StokesSystem::object_pressure_constant(int object) const {
  la::Vector z;
  check(MatCreateVecs(schur_->get(), z.out(), nullptr), "MatCreateVecs");
  PetscInt first = 0, n = 0;
  check(VecGetOwnershipRange(z.get(), &first, nullptr), "VecGetOwnershipRange");
  check(VecGetLocalSize(z.get(), &n), "VecGetLocalSize");
  PetscScalar* a = nullptr;
  check(VecGetArray(z.get(), &a), "VecGetArray");
  std::fill(a, a + n, 0.0);
  for (PetscInt d = range_.begin; d < range_.end; ++d) {
    const int dof = static_cast<int>(d);
    if (dofs_.field_of(dof) == kPressureField && dofs_.region_of(dof) == object)
      a[pressure_position_[dof] - first] = 1.0;
  }
  check(VecRestoreArray(z.get(), &a), "VecRestoreArray");
  return z;
}

std::vector<la::SparseVector> StokesSystem::rigid_motions(const mesh::Mesh& geometry,
                                                          const std::vector<int>& objects) const {
  // Each node's position in `objects` (-1: none): the nodes of an object's
  // tetrahedra, its interface included (the velocity is continuous there).
  std::vector<int> position(mesh_.n_objects + 1, -1), which(mesh_.n_nodes(), -1);
  for (std::size_t i = 0; i < objects.size(); ++i) position[objects[i]] = static_cast<int>(i);
  for (int t = 0; t < mesh_.n_tets(); ++t)
    if (const int i = position[mesh_.tet_region[t]]; i >= 0)
      for (int node : mesh_.tets[t]) which[node] = i;
  // About the centre of each object's nodes: its six vectors then have
  // comparable sizes.
  std::vector<Eigen::Vector3d> centre(objects.size(), Eigen::Vector3d::Zero());
  std::vector<int> count(objects.size(), 0);
  for (int node = 0; node < mesh_.n_nodes(); ++node)
    if (which[node] >= 0) {
      centre[which[node]] += geometry.nodes[node];
      ++count[which[node]];
    }
  for (std::size_t i = 0; i < objects.size(); ++i) centre[i] /= std::max(count[i], 1);
  // Per object: 3 translations, then 3 rotations.
  std::vector<la::SparseVector> modes(6 * objects.size());
  PetscInt local = 0;  // position among this rank's velocity unknowns
  for (PetscInt d = range_.begin; d < range_.end; ++d) {
    const int dof = static_cast<int>(d);
    if (dofs_.field_of(dof) != kVelocityField) continue;
    const int node = dofs_.node_of(dof), c = dofs_.component_of(dof);
    if (const int i = which[node]; i >= 0) {
      la::SparseVector* m = &modes[6 * i];
      const Eigen::Vector3d x = geometry.nodes[node] - centre[i];
      m[c].index.push_back(local);
      m[c].value.push_back(1.0);
      for (int r = 0; r < 3; ++r) {  // about axis r: (e_r x x)_c
        const double value = Eigen::Vector3d::Unit(r).cross(x)(c);
        if (value == 0.0) continue;
        m[3 + r].index.push_back(local);
        m[3 + r].value.push_back(value);
      }
    }
    ++local;
  }
  return modes;
}

StokesSystem::~StokesSystem() = default;

bool StokesSystem::gauge_after_solve() const {
  return settings_.method == la::SaddlePointMethod::iterative;
}

void StokesSystem::attach_pressure_nullspace() {
  // Walls and periodic faces leave the pressure free up to one constant,
  // the same in every region (the jumps are what the interfaces set).
  pressure_constant_ = la::make_vector(range_.size(), dofs_.n_dofs());
  PetscScalar* a = nullptr;
  check(VecGetArray(pressure_constant_.get(), &a), "VecGetArray");
  for (PetscInt d = range_.begin; d < range_.end; ++d)
    a[d - range_.begin] = dofs_.field_of(static_cast<int>(d)) == kPressureField ? 1.0 : 0.0;
  check(VecRestoreArray(pressure_constant_.get(), &a), "VecRestoreArray");
  // The operator is symmetric: the constant is in both null spaces, and
  // KSPSolve projects it out of the right-hand side (round-off only).
  const Vec basis = pressure_constant_.get();
  la::attach_null_space(operator_matrix(), std::span<const Vec>(&basis, 1));
}

void StokesSystem::attach_slip_pressure_nullspace(const SlipNodes& nodes) {
  // With slip a constant pressure c loads each interface with -c n on the
  // matrix side and +c n on the object's, which the multipliers lambda_a =
  // -c n_a (the matrix's traction) balance exactly, their tangential parts
  // zero: the null vector carries them, at this geometry's nodal normals.
  // Measured (unit drop, N 16, alpha 1, rtol 1e-10): 136 / 150 iterations
  // at lambda 0.1 / 10 with the gauge pinned, 112 / 126 with this null space
  // (InterfaceSlip.IterativeSolverAgreesWithTheDirectOne; the frequency
  // domain measured 46-72 against 20-35 inner iterations per solve).
  for (int node : owned_interface_nodes_) {
    const int object = interface_object_of(node);
    for (int c = 0; c < 3; ++c)
      check(VecSetValue(pressure_constant_.get(), dofs_.dof(kMultiplierField, node, object, c),
                        -nodes.normal[node](c), INSERT_VALUES),
            "VecSetValue");
  }
  check(VecAssemblyBegin(pressure_constant_.get()), "VecAssemblyBegin");
  check(VecAssemblyEnd(pressure_constant_.get()), "VecAssemblyEnd");
  const Vec basis = pressure_constant_.get();
  la::attach_null_space(operator_matrix(), std::span<const Vec>(&basis, 1));
}

void StokesSystem::move_flux_defect_to_gauge(const StokesProblem& problem, Vec rhs) const {
  // The continuity rows sum to the net boundary flux of the Dirichlet data:
  // zero for walls and periodic faces, round-off or an interpolation error
  // for data like an exact far field on a closed box. A pinned gauge drops
  // its own row and so puts that defect at the gauge; the same here keeps
  // the system consistent and its solution that of the pinned system
  // (the direct method's) instead of a least-squares compromise.
  if (problem.pressure_gauge_node < 0) return;
  PetscScalar defect = 0.0;
  check(VecDot(rhs, pressure_constant_.get(), &defect), "VecDot");
  const PetscInt p = dofs_.dof(kPressureField, problem.pressure_gauge_node, 0);
  if (range_.owns(p)) check(VecSetValue(rhs, p, -defect, ADD_VALUES), "VecSetValue");
  check(VecAssemblyBegin(rhs), "VecAssemblyBegin");
  check(VecAssemblyEnd(rhs), "VecAssemblyEnd");
}

void StokesSystem::apply_gauge(const StokesProblem& problem, Vec x) const {
  if (problem.pressure_gauge_node < 0) return;
  const double at_gauge = la::entry(x, dofs_.dof(kPressureField, problem.pressure_gauge_node, 0));
  check(VecAXPY(x, problem.pressure_gauge_value - at_gauge, pressure_constant_.get()), "VecAXPY");
}

void StokesSystem::partition() {
  const auto owned = dofs_.ownership(la::mpi_rank(), la::mpi_size());
  range_ = {owned.begin, owned.end};
  // Every element with a row here is assembled here, its other rows
  // dropped (row_dofs): an element cut by a partition boundary is computed
  // on each side, and no matrix or vector entry crosses ranks. (Sending
  // those rows to their owner instead moved a tenth of the matrix entries
  // through PETSc's stash at 152k unknowns on 2 ranks: the cut runs
  // through the finely meshed drop.) The fields the assembly reads are
  // ghosted for these elements (fem::elements_touching).
  const auto [first_node, last_node] =
      fem::rank_node_range(mesh_.n_nodes(), la::mpi_rank(), la::mpi_size());
  assembled_tets_ = fem::elements_touching(mesh_, first_node, last_node);
  // In node order (the nodes follow a space-filling curve): consecutive
  // elements then add into nearby matrix rows, which the assembly's
  // scattered adds into PETSc's value arrays need to stay in cache
  // (measured: assembly 1.61 -> 0.94 s at 374k unknowns).
  std::stable_sort(assembled_tets_.begin(), assembled_tets_.end(), [&](int a, int b) {
    return mesh_.master(mesh_.tets[a][0]) < mesh_.master(mesh_.tets[b][0]);
  });
  for (int f = 0; f < static_cast<int>(mesh_.interface_faces.size()); ++f) {
    const auto rows = interface_velocity_dofs(f, tension_region(f));
    if (std::any_of(rows.begin(), rows.end(), [&](PetscInt d) { return range_.owns(d); }))
      assembled_faces_.push_back(f);
  }
  if (slip_) {
    std::vector<char> seen(mesh_.n_nodes(), 0);
    for (int f = 0; f < static_cast<int>(mesh_.interface_faces.size()); ++f) {
      bool owns_a_row = false;
      for (int node : mesh_.interface_faces[f]) {
        const bool owned = range_.owns(dofs_.dof(kMultiplierField, node, 0));
        owns_a_row = owns_a_row || owned;
        if (!seen[node] && owned) {
          seen[node] = 1;
          owned_interface_nodes_.push_back(node);
        }
      }
      if (owns_a_row) constraint_faces_.push_back(f);
    }
  }
  std::vector<std::vector<PetscInt>> owned_by_field(dofs_.n_fields());
  for (PetscInt i = range_.begin; i < range_.end; ++i)
    owned_by_field[dofs_.field_of(static_cast<int>(i))].push_back(i);
  for (int f = 0; f < dofs_.n_fields(); ++f)
    field_index_sets_.push_back(la::make_index_set(owned_by_field[f], dofs_.field(f).components));
}

la::NullSpace StokesSystem::velocity_near_nullspace() const {
  // Coordinates of the owned velocity nodes, in the velocity block's order
  // (x, y, z triples, as the dofs come).
  std::vector<PetscScalar> xyz;
  for (PetscInt i = range_.begin; i < range_.end; ++i) {
    const int dof = static_cast<int>(i);
    if (dofs_.field_of(dof) != kVelocityField) continue;
    xyz.push_back(mesh_.nodes[dofs_.node_of(dof)](dofs_.component_of(dof)));
  }
  return la::rigid_body_modes(xyz);
}

void StokesSystem::create_matrices() {
  // One compressed-row pattern serves every solve (la::CsrMatrix). The
  // interface blocks of the semi-implicit tension are always in it (zero
  // when the tension is explicit).
  const int n = dofs_.n_dofs();
  const bool iterative = settings_.method == la::SaddlePointMethod::iterative;
  auto declare = [&](la::CsrMatrix& m, bool record) {
    for (int t : assembled_tets_) {
      const auto rows = tet_row_dofs(t);
      const auto b = m.add_block(std::span<const PetscInt>(rows), dofs_.element_dofs(t));
      if (record) tet_blocks_.push_back(b);
    }
    for (int f : assembled_faces_) {
      const auto d = interface_velocity_dofs(f, tension_region(f));
      const auto rows = row_dofs<18>(d);
      const auto b = m.add_block(std::span<const PetscInt>(rows), std::span<const PetscInt>(d));
      if (record) interface_blocks_.push_back(b);
    }
    if (slip_) {
      // Velocity rows of both copies x the face's multipliers.
      for (int f : assembled_faces_) {
        const int object = mesh_.interface_object[f];
        std::array<PetscInt, 36> rows;
        const auto outside = interface_velocity_dofs(f, 0), inside = interface_velocity_dofs(f, object);
        std::copy(outside.begin(), outside.end(), rows.begin());
        std::copy(inside.begin(), inside.end(), rows.begin() + 18);
        rows = row_dofs<36>(rows);
        const auto columns = interface_face_dofs(dofs_, mesh_, f, kMultiplierField, object);
        const auto b = m.add_block(std::span<const PetscInt>(rows), std::span<const PetscInt>(columns));
        if (record) slip_coupling_blocks_.push_back(b);
      }
      // The constraint rows of each face's nodes x (u_m, u_d, lambda) of the face.
      for (int f : constraint_faces_) {
        const int object = mesh_.interface_object[f];
        std::array<PetscInt, 54> columns;
        const auto outside = interface_velocity_dofs(f, 0), inside = interface_velocity_dofs(f, object);
        std::copy(outside.begin(), outside.end(), columns.begin());
        std::copy(inside.begin(), inside.end(), columns.begin() + 18);
        auto rows = interface_face_dofs(dofs_, mesh_, f, kMultiplierField, object);
        std::copy(rows.begin(), rows.end(), columns.begin() + 36);
        rows = row_dofs<18>(rows);
        const auto b = m.add_block(std::span<const PetscInt>(rows), std::span<const PetscInt>(columns));
        if (record) slip_constraint_blocks_.push_back(b);
      }
    }
  };
  if (iterative && !slip_) {
    create_schur_matrix();  // first: it numbers the pressure unknowns
    create_nested_matrices();
    return;
  }
  a_ = std::make_unique<la::CsrMatrix>(range_, n, range_, n);
  declare(*a_, true);
  a_->create();
  if (iterative) {
    // With slip the velocity block of the preconditioner differs from A's
    // (the jump penalty), so it gets a matrix of its own.
    pmat_ = std::make_unique<la::CsrMatrix>(range_, n, range_, n);
    declare(*pmat_, false);  // same declaration order: same block handles
    // With slip, a penalty on the jump at each interface node (preconditioner
    // only; see assemble_slip_schur_estimate).
    for (int node : owned_interface_nodes_) {
      const int object = interface_object_of(node);
      std::array<PetscInt, 6> d;
      std::array<PetscInt, 3> multipliers;
      for (int c = 0; c < 3; ++c) {
        d[c] = dofs_.dof(kVelocityField, node, 0, c);
        d[3 + c] = dofs_.dof(kVelocityField, node, object, c);
        multipliers[c] = dofs_.dof(kMultiplierField, node, object, c);
      }
      slip_penalty_blocks_.push_back(
          pmat_->add_block(std::span<const PetscInt>(d), std::span<const PetscInt>(d)));
      slip_compliance_blocks_.push_back(pmat_->add_block(
          std::span<const PetscInt>(multipliers), std::span<const PetscInt>(multipliers)));
    }
    pmat_->create();
  }
}

void StokesSystem::create_nested_matrices() {
  const int n = dofs_.n_dofs();
  std::vector<int> velocity_position(n, -1);
  int n_velocity = 0;
  for (int i = 0; i < n; ++i)
    if (dofs_.field_of(i) == kVelocityField) velocity_position[i] = n_velocity++;
  nested_ = std::make_unique<la::NestedSaddlePoint>(range_, n,
                                                    field_index_sets_[kVelocityField].get(),
                                                    field_index_sets_[kPressureField].get());
  // BoomerAMG (the velocity split's default) takes A as it is when A is in
  // hypre's format; from PETSc's AIJ it would copy it.
  if (la::primal_split_uses_hypre(settings_, dofs_.field(kVelocityField).name))
    nested_->primal().set_format(la::CsrMatrix::Format::hypre_parcsr);
  // Whole-system dofs (-1 = dropped) to their positions within a field.
  auto to = [](const std::vector<int>& position, auto first, auto last, PetscInt* out) {
    for (; first != last; ++first) *out++ = *first < 0 ? -1 : position[*first];
  };
  for (int t : assembled_tets_) {
    const auto rows = tet_row_dofs(t);
    const auto d = dofs_.element_dofs(t);
    std::array<PetscInt, kTetVelocityDofs> u_rows, u_columns;
    std::array<PetscInt, kTetPressureDofs> p_columns;
    to(velocity_position, rows.begin(), rows.begin() + kTetVelocityDofs, u_rows.data());
    to(velocity_position, d.begin(), d.begin() + kTetVelocityDofs, u_columns.data());
    to(pressure_position_, d.begin() + kTetVelocityDofs, d.end(), p_columns.data());
    tet_blocks_.push_back(nested_->primal().add_block(std::span<const PetscInt>(u_rows),
                                                      std::span<const PetscInt>(u_columns)));
    coupling_blocks_.push_back(nested_->coupling().add_block(std::span<const PetscInt>(u_rows),
                                                             std::span<const PetscInt>(p_columns)));
  }
  for (int f : assembled_faces_) {
    const auto d = interface_velocity_dofs(f, tension_region(f));
    const auto rows = row_dofs<18>(d);
    std::array<PetscInt, 18> u_rows, u_columns;
    to(velocity_position, rows.begin(), rows.end(), u_rows.data());
    to(velocity_position, d.begin(), d.end(), u_columns.data());
    interface_blocks_.push_back(nested_->primal().add_block(std::span<const PetscInt>(u_rows),
                                                            std::span<const PetscInt>(u_columns)));
  }
  nested_->create();
}

Mat StokesSystem::operator_matrix() const { return nested_ ? nested_->op() : a_->get(); }

void StokesSystem::create_schur_matrix() {
  // The pressure unknowns' positions within the pressure field, which is
  // the numbering of the Schur complement's space (PCFIELDSPLIT orders a
  // split by global index, and each rank owns a contiguous block).
  pressure_position_.assign(dofs_.n_dofs(), -1);
  PetscInt n_pressure = 0, first_owned = -1, owned = 0;
  for (int i = 0; i < dofs_.n_dofs(); ++i) {
    if (dofs_.field_of(i) != kPressureField) continue;
    if (range_.owns(i)) {
      if (first_owned < 0) first_owned = n_pressure;
      ++owned;
    }
    pressure_position_[i] = static_cast<int>(n_pressure++);
  }
  if (first_owned < 0) first_owned = n_pressure;  // this rank owns no pressure
  const la::OwnershipRange range{first_owned, first_owned + owned};
  schur_ = std::make_unique<la::CsrMatrix>(range, n_pressure, range, n_pressure);
  for (int t : assembled_tets_) {
    const auto d = dofs_.element_dofs(t);
    std::array<PetscInt, kTetPressureDofs> p, rows;  // the element's last dofs (stokes_kernels.hpp)
    for (int k = 0; k < kTetPressureDofs; ++k) {
      const int dof = d[kTetVelocityDofs + k];
      p[k] = pressure_position_[dof];
      rows[k] = range_.owns(dof) ? p[k] : -1;
    }
    schur_blocks_.push_back(
        schur_->add_block(std::span<const PetscInt>(rows), std::span<const PetscInt>(p)));
  }
  schur_->create();
}

void StokesSystem::assemble(const mesh::Mesh& geometry, const StokesProblem& problem, Vec rhs) {
  const bool iterative = pmat_ || schur_;
  // Rows of other ranks come as -1 (row_dofs).
  check(VecSetOption(rhs, VEC_IGNORE_NEGATIVE_INDICES, PETSC_TRUE), "VecSetOption");
  TetMatrix ke;
  TetVector fe;
  const auto& viscoelastic = problem.viscoelastic;
  // Each region's viscosity in -M/eta and weight on its block (schur_estimate.hpp).
  std::vector<double> mass_viscosity(problem.viscosity.size()), mass_weight(mass_viscosity.size());
  for (std::size_t r = 0; r < mass_viscosity.size(); ++r)
    mass_viscosity[r] = pressure_mass_viscosity(problem, static_cast<int>(r));
  for (std::size_t r = 0; r < mass_weight.size(); ++r)
    mass_weight[r] = r == 0 ? 1.0 : pressure_mass_weight(mass_viscosity[r] / mass_viscosity[0]);
  for (std::size_t e = 0; e < assembled_tets_.size(); ++e) {
    const int t = assembled_tets_[e];
    const int region = mesh_.tet_region[t];
    const bool has_stress =
        viscoelastic.active() && viscoelastic.models.at(region).has_conformation();
    // A viscoelastic phase: solvent viscosity mu plus the DEVSS-G theta.
    const double eta =
        problem.viscosity.at(region) + (has_stress ? viscoelastic.devss_theta(region) : 0.0);
    const auto x = fem::tet_nodes(geometry, t);
    ke.setZero();
    fe.setZero();
    PressureMass mass = PressureMass::Zero();
    add_stokes_tet_matrix(x, tabulation_, eta, ke, iterative ? &mass : nullptr,
                          mass_viscosity[region]);
    if (has_stress)
      add_viscoelastic_tet_terms(viscoelastic, fem::quadrature_points(geometry, tabulation_, t), ke,
                                 fe);
    if (nested_) {
      nested_->primal().set_block(tet_blocks_[e],
                                  ke.topLeftCorner<kTetVelocityDofs, kTetVelocityDofs>());
      nested_->coupling().set_block(coupling_blocks_[e],
                                    ke.topRightCorner<kTetVelocityDofs, kTetPressureDofs>());
    } else {
      a_->set_block(tet_blocks_[e], ke);
    }
    if (schur_) schur_->set_block(schur_blocks_[e], mass_weight[region] * mass);
    if (pmat_) {
      ke.bottomRightCorner<4, 4>() = mass;
      pmat_->set_block(tet_blocks_[e], ke);
    }
    if (problem.body_force)
      add_body_force(x, tabulation_, [&](const Vec3& xq) { return problem.body_force(xq, region); },
                     fe);
    if (problem.body_force || has_stress) {
      const auto rows = tet_row_dofs(t);  // the other rows are their owner's
      check(VecSetValues(rhs, 30, rows.data(), fe.data(), ADD_VALUES), "VecSetValues(f)");
    }
  }
  const auto& implicit = problem.semi_implicit_tension;
  for (std::size_t i = 0; i < assembled_faces_.size(); ++i) {
    const int f = assembled_faces_[i];
    const int object = mesh_.interface_object[f];
    const double gamma = object - 1 < static_cast<int>(problem.interfacial_tension.size())
                             ? problem.interfacial_tension[object - 1]
                             : 0.0;
    InterfaceMatrix block = InterfaceMatrix::Zero();
    if (gamma != 0.0) {
      const auto& tri = mesh_.interface_faces[f];
      const auto x = fem::triangle_nodes(geometry, tri);
      TriangleVelocityVector fs = TriangleVelocityVector::Zero();
      add_surface_tension(x, gamma, fs);
      if (implicit.active()) {
        // Gamma theta dt int grad_s(u.n) . grad_s(v.n) on the left, the
        // predictor's part Gamma theta dt int grad_s w . grad_s(v.n) on the right.
        const TriangleStiffness stiffness = surface_stiffness(x);
        const double scale = gamma * implicit.theta_dt;
        for (int a = 0; a < 6; ++a) {
          const Vec3& na = implicit.node_normal.at(tri[a]);
          double load = 0.0;
          for (int b = 0; b < 6; ++b) {
            const Vec3& nb = implicit.node_normal.at(tri[b]);
            block.block<3, 3>(3 * a, 3 * b) = (scale * stiffness(a, b)) * na * nb.transpose();
            load += stiffness(a, b) * implicit.predicted_normal_velocity.at(tri[b]);
          }
          fs.segment<3>(3 * a) += (scale * load) * na;
        }
      }
      const auto d = interface_velocity_dofs(f, tension_region(f));
      const auto rows = row_dofs<18>(d);  // the other rows are their owner's
      check(VecSetValues(rhs, 18, rows.data(), fs.data(), ADD_VALUES), "VecSetValues(tension)");
    }
    (nested_ ? nested_->primal() : *a_).set_block(interface_blocks_[i], block);
    if (pmat_) pmat_->set_block(interface_blocks_[i], block);
  }
  if (slip_) {
    // The nodal normals and scales serve the operator and the preconditioner.
    const SlipNodes nodes{interface_node_normals(surfaces_, geometry),
                          interface_node_scale(geometry)};
    assemble_slip(geometry, problem, nodes);
    a_->assemble();
    if (gauge_after_solve()) attach_slip_pressure_nullspace(nodes);
    if (pmat_) assemble_slip_schur_estimate(problem, nodes);
  } else if (nested_) {
    nested_->assemble();
  } else {
    a_->assemble();
  }
  if (pmat_) pmat_->assemble();
  if (schur_) schur_->assemble();
  check(VecAssemblyBegin(rhs), "VecAssemblyBegin");
  check(VecAssemblyEnd(rhs), "VecAssemblyEnd");
}

void StokesSystem::apply_dirichlet(const StokesProblem& problem, Vec rhs, Vec x) {
  // Rows and columns of constrained unknowns are eliminated symmetrically
  // (MatZeroRowsColumns), so the system stays symmetric for MINRES users.
  std::vector<PetscInt> rows;
  std::vector<PetscScalar> values;
  std::vector<char> seen(range_.size(), 0);
  auto constrain = [&](PetscInt dof, double value) {
    if (!range_.owns(dof) || seen[dof - range_.begin]) return;
    seen[dof - range_.begin] = 1;
    rows.push_back(dof);
    values.push_back(value);
  };
  for (const auto& face : mesh_.boundary_faces)
    for (int node : face) {
      const Vec3 g = problem.boundary_velocity ? problem.boundary_velocity(mesh_.nodes[node])
                                               : Vec3::Zero();
      // Outer boundary nodes lie in one region (objects never touch the box).
      for (int c = 0; c < 3; ++c) constrain(dofs_.dof(kVelocityField, node, 0, c), g(c));
    }
  if (problem.pressure_gauge_node >= 0) {
    const int p = dofs_.dof(kPressureField, problem.pressure_gauge_node, 0);
    if (p < 0) throw SolverError("pressure gauge node is not a matrix vertex");
    if (!gauge_after_solve()) constrain(p, problem.pressure_gauge_value);
  }
  if (nested_) {
    // Velocity rows only: this path never pins the gauge (gauge_after_solve).
    nested_->eliminate_primal(rows, values, rhs, x);
  } else {
    check(VecSetValues(x, static_cast<PetscInt>(rows.size()), rows.data(), values.data(),
                       INSERT_VALUES),
          "VecSetValues(x)");
    check(VecAssemblyBegin(x), "VecAssemblyBegin");
    check(VecAssemblyEnd(x), "VecAssemblyEnd");
    for (Mat m : {a_->get(), pmat_ ? pmat_->get() : Mat{}}) {
      if (!m) continue;
      const bool is_operator = m == a_->get();
      check(MatZeroRowsColumns(m, static_cast<PetscInt>(rows.size()), rows.data(), 1.0,
                               is_operator ? x : nullptr, is_operator ? rhs : nullptr),
            "MatZeroRowsColumns");
    }
  }
  if (schur_) {  // the gauge's row and column, as in the operator's pressure block
    std::vector<PetscInt> gauge;
    for (PetscInt dof : rows)
      if (pressure_position_[dof] >= 0) gauge.push_back(pressure_position_[dof]);
    check(MatZeroRowsColumns(schur_->get(), static_cast<PetscInt>(gauge.size()), gauge.data(), 1.0,
                             nullptr, nullptr),
          "MatZeroRowsColumns(Schur)");
  }
}

la::Vector StokesSystem::initial_guess(std::optional<double> step) const {
  if (!settings_.extrapolated_guess || !step || !older_solution_ || previous_step_ <= 0.0)
    return {};
  // x_n + (dt / dt_{n-1}) (x_n - x_{n-1}) (eq. 2.49's predictor): where the
  // solution changes smoothly in time it is O(dt^2) from x_{n+1}, the last
  // solution O(dt).
  const auto e = time::extrapolation(2, *step, previous_step_);
  la::Vector guess;
  check(VecDuplicate(previous_solution_.get(), guess.out()), "VecDuplicate");
  check(VecAXPBYPCZ(guess.get(), e.current, e.previous, 0.0, previous_solution_.get(),
                    older_solution_.get()),
        "VecAXPBYPCZ");
  return guess;
}

namespace {

la::Vector copy_of(Vec x) {
  la::Vector v;
  check(VecDuplicate(x, v.out()), "VecDuplicate");
  check(VecCopy(x, v.get()), "VecCopy");
  return v;
}

}  // namespace

void StokesSystem::keep_solution(Vec x, std::optional<double> step) {
  // The history before this solve, for rewind_guess_history.
  undo_previous_ = std::move(previous_solution_);
  undo_older_ = std::move(older_solution_);
  undo_step_ = previous_step_;
  ++solves_;
  // Both kept solutions must have ended steps for their line to be one in time.
  if (step && undo_previous_ && undo_step_ > 0.0) older_solution_ = copy_of(undo_previous_.get());
  previous_solution_ = copy_of(x);
  previous_step_ = step.value_or(0.0);
}

void StokesSystem::rewind_guess_history(long mark) {
  if (solves_ == mark) return;
  if (solves_ == mark + 1) {
    previous_solution_ = std::move(undo_previous_);
    older_solution_ = std::move(undo_older_);
    previous_step_ = undo_step_;
    solves_ = mark;
    return;
  }
  restart_guess_history();
}

StokesResult StokesSystem::solve(const StokesProblem& problem, SolutionLayout layout,
                                 std::optional<double> step) {
  if (problem.semi_implicit_tension.active() &&
      (static_cast<int>(problem.semi_implicit_tension.node_normal.size()) < mesh_.n_nodes() ||
       static_cast<int>(problem.semi_implicit_tension.predicted_normal_velocity.size()) <
           mesh_.n_nodes()))
    throw SolverError("StokesProblem: semi-implicit tension needs a normal and a normal "
                      "velocity for every mesh node");
  if (problem.slip.any() && !slip_)
    throw SolverError("StokesProblem: slip on an interface needs a StokesSystem built with "
                      "interface_slip = true");
  if (static_cast<int>(problem.viscosity.size()) < mesh_.n_objects + 1)
    throw SolverError(fmt::format("StokesProblem: {} viscosities for {} regions",
                                  problem.viscosity.size(), mesh_.n_objects + 1));
  const auto start = std::chrono::steady_clock::now();
  la::Vector guess = initial_guess(step);
  auto [rhs, x] = assemble_system(mesh_, problem, guess ? guess.get() : previous_solution_.get());
  StokesResult result;
  result.assembly_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (factors_are_off_step(problem)) solver_->refactor_at_next_solve();
  const int setups = solver_->n_setups();
  result.solve = solver_->solve(rhs.get(), x.get(), static_cast<bool>(previous_solution_));
  if (solver_->n_setups() > setups) record_factorization(problem);
  if (gauge_after_solve()) apply_gauge(problem, x.get());
  keep_solution(x.get(), step);
  if (layout == SolutionLayout::gathered) result.solution = la::gather_to_all(x.get());
  result.distributed = std::move(x);
  return result;
}

/// LU factors precondition a matrix whose semi-implicit tension term
/// (Gamma theta dt times a surface Laplacian) is kStaleStepRatio times
/// larger or smaller than theirs poorly, though GMRES still converges
/// within max_reuse_iterations: adaptive steps growing from 0.005 to 0.1 on
/// factors of the first step took 5.7 iterations a step where constant
/// steps take 2.7 (docs/time_stepping.md, "Default steps"). Steps that
/// double every time refactor every second step until they settle; a
/// constant step's BDF1-to-BDF2 change (theta dt from dt to 2 dt / 3) does
/// not. The record is part of the saved state, so a restart decides alike.
constexpr double kStaleStepRatio = 2.0;

bool StokesSystem::factors_are_off_step(const StokesProblem& problem) const {
  if (settings_.method != la::SaddlePointMethod::direct || !factors_) return false;
  const double then = factors_->problem.semi_implicit_tension.theta_dt;
  const double now = problem.semi_implicit_tension.theta_dt;
  if (!(then > 0.0) || !(now > 0.0)) return false;
  return now > kStaleStepRatio * then || then > kStaleStepRatio * now;
}

void StokesSystem::record_factorization(const StokesProblem& problem) {
  MatrixRecord r{mesh_.nodes, {}, {}, {}, false};
  r.problem.viscosity = problem.viscosity;
  r.problem.interfacial_tension = problem.interfacial_tension;
  r.problem.pressure_gauge_node = problem.pressure_gauge_node;
  r.problem.slip = problem.slip;
  r.problem.semi_implicit_tension.theta_dt = problem.semi_implicit_tension.theta_dt;
  if (problem.semi_implicit_tension.active())
    r.problem.semi_implicit_tension.node_normal = problem.semi_implicit_tension.node_normal;
  if (const auto& ve = problem.viscoelastic; ve.active()) {
    r.problem.viscoelastic.models = ve.models;
    r.problem.viscoelastic.dt = ve.dt;
    r.problem.viscoelastic.bdf = ve.bdf;
    r.problem.viscoelastic.extrapolation = ve.extrapolation;
    r.conformation = la::owned_values(ve.conformation->vector());
    if (ve.previous_conformation)
      r.previous_conformation = la::owned_values(ve.previous_conformation->vector());
    r.devss = ve.velocity_gradient != nullptr;
  }
  // MUMPS's symbolic analysis: the direct method's only.
  if (!analysis_ && settings_.method == la::SaddlePointMethod::direct) analysis_ = r;
  factors_ = std::move(r);
}

TriangleNormals StokesSystem::SlipNodes::of(const std::array<int, 6>& tri) const {
  TriangleNormals out;
  for (int a = 0; a < 6; ++a) out[a] = normal[tri[a]];
  return out;
}

void StokesSystem::assemble_slip(const mesh::Mesh& geometry, const StokesProblem& problem,
                                 const SlipNodes& nodes) {
  const bool iterative = static_cast<bool>(pmat_);  // with slip, the only preconditioning matrix
  for (std::size_t i = 0; i < assembled_faces_.size(); ++i) {
    const auto& tri = mesh_.interface_faces[assembled_faces_[i]];
    const auto c = slip_coupling_matrix(fem::triangle_nodes(geometry, tri), nodes.of(tri));
    Eigen::Matrix<double, 36, 18> block;
    block << c, -c;  // + integral lambda_h . v_m, - integral lambda_h . v_d
    a_->set_block(slip_coupling_blocks_[i], block);
    if (iterative) pmat_->set_block(slip_coupling_blocks_[i], block);
  }
  // The constraint rows: the transpose of the coupling, less alpha times
  // the tangential multipliers' mass (interface_slip.hpp). The
  // preconditioning matrix takes the same and adds its Schur estimate
  // (assemble_slip_schur_estimate).
  for (std::size_t i = 0; i < constraint_faces_.size(); ++i) {
    const int f = constraint_faces_[i];
    const auto& tri = mesh_.interface_faces[f];
    const double alpha = problem.slip.of(mesh_.interface_object[f]);
    if (!(alpha >= 0.0))
      throw SolverError(fmt::format("StokesProblem: slip coefficient {} of object {} (allowed: "
                                    ">= 0, inf for free slip)", alpha, mesh_.interface_object[f]));
    const auto x = fem::triangle_nodes(geometry, tri);
    const auto block =
        slip_constraint_block(slip_coupling_matrix(x, nodes.of(tri)), surface_mass(x), nodes.of(tri), alpha);
    a_->set_block(slip_constraint_blocks_[i], block);
    if (iterative) pmat_->set_block(slip_constraint_blocks_[i], block);
  }
}

void StokesSystem::assemble_slip_schur_estimate(const StokesProblem& problem,
                                                const SlipNodes& nodes) {
  // The jump penalty and the multipliers' Schur estimate of
  // slip_node_preconditioner, from A's diagonal.
  la::Vector diagonal = la::make_vector(range_.size(), dofs_.n_dofs());
  check(MatGetDiagonal(a_->get(), diagonal.get()), "MatGetDiagonal");
  const PetscScalar* a = nullptr;
  check(VecGetArrayRead(diagonal.get(), &a), "VecGetArrayRead");
  for (std::size_t i = 0; i < owned_interface_nodes_.size(); ++i) {
    const int node = owned_interface_nodes_[i];
    const int object = interface_object_of(node);
    const auto p =
        slip_node_preconditioner(dofs_, a, static_cast<int>(range_.begin), node, object,
                                 nodes.normal[node], nodes.scale[node], problem.slip.of(object));
    pmat_->set_block(slip_penalty_blocks_[i], p.jump_penalty);
    pmat_->set_block(slip_compliance_blocks_[i], p.schur_estimate);
  }
  check(VecRestoreArrayRead(diagonal.get(), &a), "VecRestoreArrayRead");
}

std::pair<la::Vector, la::Vector> StokesSystem::assemble_system(
    const mesh::Mesh& geometry, const StokesProblem& problem, Vec guess) {
  la::Vector rhs = la::make_vector(range_.size(), dofs_.n_dofs());
  la::Vector x = la::make_vector(range_.size(), dofs_.n_dofs());
  check(VecSet(rhs.get(), 0.0), "VecSet");
  // apply_dirichlet then puts the boundary values in.
  if (guess) check(VecCopy(guess, x.get()), "VecCopy");
  else check(VecSet(x.get(), 0.0), "VecSet");
  assemble(geometry, problem, rhs.get());
  apply_dirichlet(problem, rhs.get(), x.get());
  if (gauge_after_solve()) move_flux_defect_to_gauge(problem, rhs.get());
  assembled_geometry_ = &geometry;
  if (schur_) update_coarse_spaces(problem);
  solver_->set_operators(operator_matrix(),
                         nested_ ? nested_->preconditioning() : pmat_ ? pmat_->get() : nullptr,
                         schur_ ? schur_->get() : nullptr);
  return {std::move(rhs), std::move(x)};
}

void StokesSystem::factor(const MatrixRecord& record) {
  mesh::Mesh geometry = mesh_;
  geometry.nodes = record.nodes;
  StokesProblem problem = record.problem;
  if (problem.semi_implicit_tension.active())
    problem.semi_implicit_tension.predicted_normal_velocity.assign(mesh_.n_nodes(), 0.0);
  // The viscoelastic terms' matrix reads c_n, c_{n-1} (the prediction's
  // c*), the BDF step and whether DEVSS-G was on (its theta); the loads
  // (u_m, G_n, the defect) do not matter here: zero fields.
  std::optional<fem::Field> conformation, previous_conformation, velocity_gradient;
  problem.viscoelastic.defect = nullptr;
  if (!record.conformation.empty()) {
    conformation.emplace(conformation_field(record.conformation));
    problem.viscoelastic.conformation = &*conformation;
    if (!record.previous_conformation.empty()) {
      previous_conformation.emplace(conformation_field(record.previous_conformation));
      problem.viscoelastic.previous_conformation = &*previous_conformation;
    }
    if (record.devss) {
      velocity_gradient.emplace(mesh_, "velocity_gradient", conformation->dofs().field(0).space,
                                kVelocityGradientComponents);
      problem.viscoelastic.velocity_gradient = &*velocity_gradient;
    }
  }
  assemble_system(geometry, problem);  // the matrix is what counts; the vectors go
  solver_->set_up();
  assembled_geometry_ = &mesh_;  // not the local copy, gone on return
}

fem::Field StokesSystem::conformation_field(const std::vector<double>& owned_values) const {
  // The space of every conformation field: P1, one copy per region.
  const auto space = std::make_shared<fem::Space>(mesh_, 1, fem::Continuity::per_region);
  fem::Field conformation(mesh_, "conformation", space, 6);
  if (!owned_values.empty()) {  // else zero
    la::set_owned_values(conformation.vector(), owned_values);
    conformation.update_ghosts();
  }
  return conformation;
}

StatePart StokesSystem::state_part() {
  return {"stokes",
          [this](StateRecord& r, const std::string& p) { save_state(r, p); },
          [this](const StateRecord& r, const std::string& p) { restore_state(r, p); }};
}

namespace {

void save_matrix_record(StateRecord& out, const std::string& prefix,
                        const std::vector<mesh::Point>& nodes, const StokesProblem& problem) {
  out.set(prefix + "nodes", nodes);
  out.set(prefix + "viscosity", problem.viscosity);
  out.set(prefix + "interfacial_tension", problem.interfacial_tension);
  out.set(prefix + "pressure_gauge_node", problem.pressure_gauge_node);
  out.set(prefix + "slip", problem.slip.coefficient);
  out.set(prefix + "theta_dt", problem.semi_implicit_tension.theta_dt);
  out.set(prefix + "node_normal", problem.semi_implicit_tension.node_normal);
  // Each region's model by its identity: the model and the values that
  // rebuild it (Constitutive::create), one array per parameter, NaN where
  // unset; dt.
  std::vector<double> kinds;
  std::map<std::string, std::vector<double>> values;
  for (const auto& m : problem.viscoelastic.models) {
    kinds.push_back(static_cast<double>(m.model()));
    const viscoelastic::ConstitutiveValues identity = m.values();
    viscoelastic::for_each_parameter(identity, [&](std::string_view key, std::string_view,
                                                    const std::optional<double>& v) {
      values[std::string(key)].push_back(v.value_or(std::nan("")));
    });
  }
  out.set(prefix + "viscoelastic_model", kinds);
  for (auto& [key, v] : values) out.set(prefix + "viscoelastic_values/" + key, std::move(v));
  out.set(prefix + "viscoelastic_dt", problem.viscoelastic.dt);
  const auto& bdf = problem.viscoelastic.bdf;
  const auto& e = problem.viscoelastic.extrapolation;
  out.set(prefix + "viscoelastic_bdf", std::vector<double>{bdf.a0, bdf.a1, bdf.a2});
  out.set(prefix + "viscoelastic_extrapolation", std::vector<double>{e.current, e.previous});
}

}  // namespace

void StokesSystem::save_state(StateRecord& out, const std::string& prefix) const {
  // The next solve's initial guess: a restarted run iterates from the same
  // vector as an uninterrupted one.
  out.set(prefix + "initial_guess", previous_solution_ ? la::gather_to_all(previous_solution_.get())
                                                      : std::vector<double>{});
  out.set(prefix + "older_solution",
          older_solution_ ? la::gather_to_all(older_solution_.get()) : std::vector<double>{});
  out.set(prefix + "previous_step", previous_step_);
  out.set(prefix + "refactor_next", solver_->refactor_next());
  out.set(prefix + "n_factorizations", solver_->n_setups());
  out.set(prefix + "fewest_iterations", solver_->fewest_iterations());
  out.set(prefix + "has_factors", factors_.has_value());
  if (!factors_) return;
  std::vector<std::pair<std::string, const MatrixRecord*>> records{{"factors/", &*factors_}};
  if (analysis_) records.emplace_back("analysis/", &*analysis_);
  for (const auto& [name, record] : records) {
    save_matrix_record(out, prefix + name, record->nodes, record->problem);
    // Every rank's values, in the field's global numbering, whatever the
    // number of ranks of the run that restarts.
    out.set(prefix + name + "conformation",
            record->conformation.empty()
                ? std::vector<double>{}
                : conformation_field(record->conformation).gather());
    out.set(prefix + name + "previous_conformation",
            record->previous_conformation.empty()
                ? std::vector<double>{}
                : conformation_field(record->previous_conformation).gather());
    out.set(prefix + name + "devss", record->devss);
  }
}

void StokesSystem::restore_state(const StateRecord& in, const std::string& prefix) {
  // Checkpoints from before the guess was kept: the next solve starts from
  // zero; from before the older solution was: from the last one.
  auto read_solution = [&](const std::string& key) {
    la::Vector v;
    if (!in.contains(prefix + key)) return v;
    const auto& values = in.get_array(prefix + key);
    if (!values.empty() && static_cast<PetscInt>(values.size()) != dofs_.n_dofs())
      throw InputError(fmt::format("the saved state's {}{} has {} values for {} unknowns", prefix,
                                   key, values.size(), dofs_.n_dofs()));
    if (!values.empty()) {
      v = la::make_vector(range_.size(), dofs_.n_dofs());
      la::scatter_from_all(v.get(), values);
    }
    return v;
  };
  previous_solution_ = read_solution("initial_guess");
  older_solution_ = read_solution("older_solution");
  previous_step_ =
      in.contains(prefix + "previous_step") ? in.get_double(prefix + "previous_step") : 0.0;
  // Either method rebuilds the preconditioner an uninterrupted run would
  // still be using (the direct method's factors, the iterative method's
  // sub-matrices and AMG hierarchy).
  if (in.get_bool(prefix + "has_factors")) {
    auto read = [&](const std::string& p) {
      MatrixRecord r{in.get_points(p + "nodes"), {}, {}, {}, false};
      if (static_cast<int>(r.nodes.size()) != mesh_.n_nodes())
        throw InputError(fmt::format("the saved state's {}nodes do not fit the mesh", p));
      r.problem.viscosity = in.get_array(p + "viscosity");
      r.problem.interfacial_tension = in.get_array(p + "interfacial_tension");
      r.problem.pressure_gauge_node = in.get_int(p + "pressure_gauge_node");
      // Checkpoints from before slip existed: no slip.
      if (in.contains(p + "slip")) r.problem.slip.coefficient = in.get_array(p + "slip");
      r.problem.semi_implicit_tension.theta_dt = in.get_double(p + "theta_dt");
      r.problem.semi_implicit_tension.node_normal = in.get_points(p + "node_normal");
      // Checkpoints of Newtonian runs from before the viscoelastic phases
      // have no such entries: nothing viscoelastic in their matrices.
      if (!in.contains(p + "conformation")) return r;
      if (in.contains(p + "viscoelastic_model")) {
        const auto& kinds = in.get_array(p + "viscoelastic_model");
        for (std::size_t region = 0; region < kinds.size(); ++region) {
          viscoelastic::ConstitutiveValues values;
          viscoelastic::for_each_parameter(
              values, [&](std::string_view key, std::string_view, std::optional<double>& v) {
                const std::string name = p + "viscoelastic_values/" + std::string(key);
                if (!in.contains(name)) return;  // a parameter newer than the checkpoint
                const auto& saved = in.get_array(name);
                if (region < saved.size() && !std::isnan(saved[region])) v = saved[region];
              });
          r.problem.viscoelastic.models.push_back(viscoelastic::Constitutive::create(
              static_cast<viscoelastic::ConstitutiveModel>(std::lround(kinds[region])), values));
        }
      } else {
        // Checkpoints from before the identity was saved by values():
        // rows (model, mu, G, lambda, alpha).
        const auto& models = in.get_array(p + "viscoelastic_models", 5);
        for (std::size_t i = 0; i + 5 <= models.size(); i += 5)
          r.problem.viscoelastic.models.push_back(viscoelastic::Constitutive::from_parameters(
              static_cast<viscoelastic::ConstitutiveModel>(std::lround(models[i])), models[i + 1],
              models[i + 2], models[i + 3], models[i + 4]));
      }
      r.problem.viscoelastic.dt = in.get_double(p + "viscoelastic_dt");
      // Checkpoints from before the consistent prediction: the Euler step.
      if (in.contains(p + "viscoelastic_bdf")) {
        const auto& a = in.get_array(p + "viscoelastic_bdf");
        const auto& e = in.get_array(p + "viscoelastic_extrapolation");
        r.problem.viscoelastic.bdf = {a.at(0), a.at(1), a.at(2)};
        r.problem.viscoelastic.extrapolation = {e.at(0), e.at(1)};
      }
      auto owned = [&](const std::string& key) {
        if (!in.contains(p + key)) return std::vector<double>{};
        const auto& all = in.get_array(p + key);
        if (all.empty()) return std::vector<double>{};
        fem::Field field = conformation_field({});
        if (static_cast<int>(all.size()) != field.dofs().n_dofs())
          throw InputError(fmt::format("the saved state's {}{} does not fit the mesh", p, key));
        field.scatter(all);
        return la::owned_values(field.vector());
      };
      r.conformation = owned("conformation");
      r.previous_conformation = owned("previous_conformation");
      r.devss = in.get_bool(p + "devss");
      return r;
    };
    factors_ = read(prefix + "factors/");
    analysis_.reset();
    if (settings_.method != la::SaddlePointMethod::direct) {
      factor(*factors_);
    } else {
      // MUMPS keeps the symbolic analysis of its first factorisation for
      // later numeric ones of the same pattern: factor that matrix first.
      analysis_ = read(prefix + "analysis/");
      factor(*analysis_);
      // Each rank holds its own part of the conformation: whether the two
      // differ anywhere is agreed on, so that every rank factors or none.
      const auto& f = factors_->problem.viscoelastic;
      const auto& a = analysis_->problem.viscoelastic;
      int conformation_differs =
          factors_->conformation != analysis_->conformation ||
                  factors_->previous_conformation != analysis_->previous_conformation ||
                  f.bdf != a.bdf || f.extrapolation != a.extrapolation
              ? 1
              : 0;
      MPI_Allreduce(MPI_IN_PLACE, &conformation_differs, 1, MPI_INT, MPI_LOR, PETSC_COMM_WORLD);
      if (factors_->nodes != analysis_->nodes ||
          factors_->problem.semi_implicit_tension.theta_dt !=
              analysis_->problem.semi_implicit_tension.theta_dt ||
          conformation_differs || factors_->devss != analysis_->devss ||
          factors_->problem.slip.coefficient != analysis_->problem.slip.coefficient)
        factor(*factors_);
    }
  }
  // Checkpoints from before the iterative method kept its preconditioner: none kept.
  solver_->restore_reuse_state(in.get_bool(prefix + "refactor_next"),
                               in.get_int(prefix + "n_factorizations"),
                               in.contains(prefix + "fewest_iterations")
                                   ? in.get_int(prefix + "fewest_iterations")
                                   : 0);
}

std::array<PetscInt, 18> interface_face_dofs(const fem::DofMap& dofs, const mesh::Mesh& mesh, int face, int field,
                                             int region) {
  const auto& tri = mesh.interface_faces[face];
  std::array<PetscInt, 18> out;
  for (int k = 0; k < 6; ++k)
    for (int c = 0; c < 3; ++c) out[3 * k + c] = dofs.dof(field, tri[k], region, c);
  return out;
}

std::array<PetscInt, 18> StokesSystem::interface_velocity_dofs(int face, int region) const {
  return interface_face_dofs(dofs_, mesh_, face, kVelocityField, region);
}

int StokesSystem::interface_object_of(int node) const {
  return dofs_.region_of(dofs_.dof(kMultiplierField, node, 0));
}

int StokesSystem::tension_region(int face) const {
  return slip_ ? mesh_.interface_object[face] : 0;
}

int default_pressure_gauge_node(const mesh::Mesh& mesh) {
  // The bottom-wall vertex nearest the wall's centre (0, -H/2, 0): away from
  // the box corners, where the P1 pressure is least well determined, and far
  // from objects placed in the cell's interior.
  const mesh::Point target(0.0, -mesh.box.height / 2, 0.0);
  int best = -1;
  double best_distance = 0.0;
  for (std::size_t f = 0; f < mesh.boundary_faces.size(); ++f) {
    if (mesh.boundary_face_tag[f] != mesh::BoundaryTag::wall_bottom) continue;
    for (int k = 0; k < 3; ++k) {
      const int node = mesh.master(mesh.boundary_faces[f][k]);
      const double d = (mesh.nodes[node] - target).norm();
      if (best < 0 || d < best_distance || (d == best_distance && node < best)) {
        best_distance = d;
        best = node;
      }
    }
  }
  if (best < 0) {
    // No walls (test boxes): any matrix vertex will do; take the first.
    for (int t = 0; t < mesh.n_tets() && best < 0; ++t)
      if (mesh.tet_region[t] == 0) best = mesh.tets[t][0];
  }
  return best;
}

}  // namespace softflow::physics
