#include "softflow/physics/stokes/oscillatory_response.hpp"

#include <algorithm>
#include <chrono>
#include <string_view>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/fem/field.hpp"
#include "softflow/la/csr_matrix.hpp"
#include "softflow/la/saddle_point_solver.hpp"
#include "softflow/la/vector_values.hpp"
#include "softflow/physics/stokes/interface_slip.hpp"
#include "softflow/physics/stokes/stokes_kernels.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"

namespace softflow::physics {

namespace {

using la::check;
constexpr int kQuadratureDegree = 5;  // as StokesSystem's

}  // namespace

namespace {

/// N^T k N: a scalar operator k on the normal components at the 6 nodes.
Eigen::Matrix<double, 18, 18> on_normal_components(const TriangleStiffness& k,
                                                   const std::array<Eigen::Vector3d, 6>& normals) {
  Eigen::Matrix<double, 18, 18> block;
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b) block.block<3, 3>(3 * a, 3 * b) = k(a, b) * normals[a] * normals[b].transpose();
  return block;
}

}  // namespace

Eigen::Matrix<double, 18, 18> linearised_tension_block(
    const element::TriangleNodes& x, const std::array<Eigen::Vector3d, 6>& normals, double gamma,
    double radius) {
  return on_normal_components(
      gamma * (surface_stiffness(x) - (2.0 / (radius * radius)) * surface_mass(x)), normals);
}

Eigen::Matrix<double, 18, 18> normal_surface_stiffness_block(
    const element::TriangleNodes& x, const std::array<Eigen::Vector3d, 6>& normals, double gamma) {
  return on_normal_components(gamma * surface_stiffness(x), normals);
}

struct OscillatorySystem::Impl {
  std::unique_ptr<la::CsrMatrix> matrix;  // the real form, 2N
  // Per assembled tet: its real and imaginary blocks; per face: the two couplings.
  std::vector<la::CsrMatrix::Block> real_blocks, imaginary_blocks, upper_blocks, lower_blocks;
  // With slip, per face and part: the multipliers' coupling and the constraint rows.
  std::vector<std::array<la::CsrMatrix::Block, 2>> slip_coupling_blocks, slip_constraint_blocks;
  /// The direct path: one LU solver for every frequency. The pattern does
  /// not change, so MUMPS's analysis (ordering, symbolic factorisation) is
  /// done once and each frequency only factors numerically.
  la::Solver lu;

  // The iterative path (N-size): K + B, its preconditioning matrix, B.
  std::unique_ptr<la::CsrMatrix> inner, inner_pmat, coupling;
  std::vector<la::CsrMatrix::Block> inner_tet_blocks, inner_face_blocks, pmat_tet_blocks, pmat_face_blocks,
      coupling_blocks;
  // With slip, per face: (coupling, constraint) in K + B and in its
  // preconditioning matrix; per owned interface node: the preconditioner's
  // jump penalty and Schur estimate (slip_node_preconditioner).
  std::vector<std::array<la::CsrMatrix::Block, 2>> inner_slip_blocks, pmat_slip_blocks;
  std::vector<std::pair<int, int>> slip_nodes;  // (node, object)
  std::vector<std::array<la::CsrMatrix::Block, 2>> slip_node_blocks;
  std::vector<double> node_scale;  // interface_node_scale
  std::vector<la::IndexSet> field_sets;
  la::NullSpace near_nullspace;
  std::unique_ptr<la::SaddlePointSolver> inner_solver;
  la::Solver outer;
  la::Vector a, b, z, y, bz;  // PRESB's work vectors (N-size)
  /// The iterative path's gauge: the pressure is left free up to a constant
  /// (a null space) instead of pinned at one vertex, and shifted to the
  /// gauge after the solve. A pinned pressure slows the inner Stokes solves
  /// (StokesSystem measured 60 -> 38 iterations for the same change).
  /// The constant pressure of each part of the real form (2N), kept for the shift.
  std::array<la::Vector, 2> pressure_constant;
  int inner_solves = 0, inner_iterations = 0;

  /// x = (K + B)^{-1} r by the inner solver.
  void inner_solve(Vec r, Vec x) {
    check(VecSet(x, 0.0), "VecSet");
    const la::SolveReport report = inner_solver->solve(r, x);
    ++inner_solves;
    inner_iterations += report.iterations;
  }
};

namespace {

/// Whether the inner solves follow each AMG cycle of the velocity block
/// by an exact solve on the interface nodes' velocities (la::make_block_corrected).
///
/// Why: the tension's block B = T / omega couples the three components of
/// each interface node through n n^T with the stiffness Gamma / omega, which
/// outweighs the viscous block by Gamma / (omega eta R) (eta the lower of
/// the two phases' viscosities) at low frequency or low viscosity ratio.
/// BoomerAMG's cycles lose their grip there: 10 inner iterations a solve
/// at omega* = 10 but 48 at 0.2 (4 drops, lambda = 0.1), 91 on the 24-drop
/// phi = 0.2 configurations. With the velocity block factored exactly
/// instead the same solves take 18, so the AMG fails, not the Schur
/// estimate. Scalar AMG (no block size) made it worse (72), a coarse
/// space of the drops' translations did nothing (48; the preconditioning
/// matrix's B lacks the -2/R^2 mass term, so it stiffens them), and on one
/// drop (omega* = 0.002) nodal coarsening and a lower strength threshold
/// did not help either. The exact
/// block is the interface's part of the velocity block (a surface-like
/// pattern, cheap to factor). Measured (benchmarks/interface_block.md, the
/// 4 drops, 174k real unknowns): 48 -> 31 inner iterations a solve and
/// 0.71 of the time at a ratio of 50, 0.81 at 25, 0.96 at 10 and 1.16 at 1
/// (the factorisation and one more product a cycle, for nothing), so it
/// is used from a ratio of 20. Not beyond 100, where it was not measured
/// to pay: one drop at ratio 500 (omega* = 0.002, lambda = 1) took 22
/// FGMRES iterations with it against at most 15 without. Not with slip:
/// at alpha = 1, omega* = 0.02 (ratio 50) it took 17 FGMRES iterations
/// against at most 12 and ended 3.5e-5 (relative) from the LU's solution,
/// over the 1e-5 its test allows (test_oscillatory_response).
/// -oscillatory_interface_block always|never overrides the rule.
bool interface_block_pays(const OscillatoryProblem& problem, bool slip) {
  char choice[16] = "";
  PetscBool set = PETSC_FALSE;
  check(PetscOptionsGetString(nullptr, nullptr, "-oscillatory_interface_block", choice,
                              sizeof choice, &set),
        "PetscOptionsGetString");
  if (set) {
    const std::string_view c(choice);
    if (c == "always") return true;
    if (c == "never") return false;
    throw InputError(
        fmt::format("-oscillatory_interface_block {}: allowed are always and never", c));
  }
  if (slip) return false;
  constexpr double kStiffnessRatioFrom = 20.0, kStiffnessRatioTo = 100.0;
  double ratio = 0.0;
  for (std::size_t k = 0; k < problem.interfacial_tension.size(); ++k) {
    const double eta = std::min(problem.viscosity.at(0), problem.viscosity.at(k + 1));
    ratio = std::max(ratio,
                     problem.interfacial_tension[k] / (problem.omega * eta * problem.radius.at(k)));
  }
  return ratio >= kStiffnessRatioFrom && ratio <= kStiffnessRatioTo;
}

/// PRESB's application to the residual (r_r, r_i), interleaved as the real
/// form's unknowns (OscillatorySystem's header derives it):
///   z = S (r_r - r_i),  y = S (-r_i - B z),  out = (z - y, -y),  S = (K + B)^{-1}.
PetscErrorCode apply_presb(PC pc, Vec residual, Vec out) {
  void* context = nullptr;
  PetscCall(PCShellGetContext(pc, &context));
  auto& impl = *static_cast<OscillatorySystem::Impl*>(context);
  PetscInt n = 0;
  PetscCall(VecGetLocalSize(impl.a.get(), &n));
  {
    const PetscScalar* r = nullptr;
    PetscScalar *a = nullptr, *b = nullptr;
    PetscCall(VecGetArrayRead(residual, &r));
    PetscCall(VecGetArray(impl.a.get(), &a));
    PetscCall(VecGetArray(impl.b.get(), &b));
    for (PetscInt i = 0; i < n; ++i) {
      a[i] = r[2 * i] - r[2 * i + 1];
      b[i] = -r[2 * i + 1];
    }
    PetscCall(VecRestoreArray(impl.b.get(), &b));
    PetscCall(VecRestoreArray(impl.a.get(), &a));
    PetscCall(VecRestoreArrayRead(residual, &r));
  }
  try {
    impl.inner_solve(impl.a.get(), impl.z.get());
    PetscCall(MatMult(impl.coupling->get(), impl.z.get(), impl.bz.get()));
    PetscCall(VecAXPY(impl.b.get(), -1.0, impl.bz.get()));
    impl.inner_solve(impl.b.get(), impl.y.get());
  } catch (const std::exception&) {
    return PETSC_ERR_NOT_CONVERGED;  // KSPSolve reports the failure; the message is in the exception's text
  }
  const PetscScalar *z = nullptr, *y = nullptr;
  PetscScalar* o = nullptr;
  PetscCall(VecGetArrayRead(impl.z.get(), &z));
  PetscCall(VecGetArrayRead(impl.y.get(), &y));
  PetscCall(VecGetArray(out, &o));
  for (PetscInt i = 0; i < n; ++i) {
    o[2 * i] = z[i] - y[i];
    o[2 * i + 1] = -y[i];
  }
  PetscCall(VecRestoreArray(out, &o));
  PetscCall(VecRestoreArrayRead(impl.y.get(), &y));
  PetscCall(VecRestoreArrayRead(impl.z.get(), &z));
  return 0;
}

}  // namespace

OscillatorySystem::OscillatorySystem(const mesh::Mesh& mesh, la::SaddlePointMethod method, bool interface_slip)
    : mesh_(mesh),
      dofs_(make_stokes_dof_map(mesh, interface_slip)),
      tabulation_(kQuadratureDegree),
      impl_(std::make_unique<Impl>()) {
  for (int k = 1; k <= mesh_.n_objects; ++k) surfaces_.push_back(extract_interface(mesh_, k));
  node_normal_ = interface_node_normals(surfaces_, mesh_);
  slip_ = interface_slip;
  method_ = method;
  if (method_ == la::SaddlePointMethod::automatic) {
    method_ = n_unknowns() <= la::kDirectSolverLimit ? la::SaddlePointMethod::direct
                                                       : la::SaddlePointMethod::iterative;
    method_reason_ = fmt::format("auto: {} real unknowns, {} the {} an LU factorisation fits in memory for",
                                 n_unknowns(), n_unknowns() <= la::kDirectSolverLimit ? "within" : "above",
                                 la::kDirectSolverLimit);
  } else {
    method_reason_ = "as the case asks (solver.type)";
  }
  const auto owned = dofs_.ownership(la::mpi_rank(), la::mpi_size());
  range_ = {index(owned.begin, 0), index(owned.end, 0)};
  // As StokesSystem: every element with a row here is assembled here.
  const auto [first_node, last_node] = fem::rank_node_range(mesh_.n_nodes(), la::mpi_rank(), la::mpi_size());
  assembled_tets_ = fem::elements_touching(mesh_, first_node, last_node);
  create_matrix();
  if (method_ == la::SaddlePointMethod::iterative) create_inner_matrices();
}

OscillatorySystem::~OscillatorySystem() = default;

void OscillatorySystem::create_matrix() {
  const PetscInt n = n_unknowns();
  impl_->matrix = std::make_unique<la::CsrMatrix>(range_, n, range_, n);
  auto& m = *impl_->matrix;
  auto part_of = [&](const auto& dofs, int part, bool rows) {
    std::vector<PetscInt> out(dofs.size());
    for (std::size_t k = 0; k < dofs.size(); ++k) {
      out[k] = index(dofs[k], part);
      if (rows && !range_.owns(out[k])) out[k] = -1;  // its owner assembles it
    }
    return out;
  };
  for (int t : assembled_tets_) {
    const auto dofs = dofs_.element_dofs(t);
    for (int part : {0, 1}) {
      const auto rows = part_of(dofs, part, true), columns = part_of(dofs, part, false);
      (part == 0 ? impl_->real_blocks : impl_->imaginary_blocks)
          .push_back(m.add_block(std::span<const PetscInt>(rows), std::span<const PetscInt>(columns)));
    }
  }
  for (int f = 0; f < n_faces(); ++f) {
    const auto d = interface_face_dofs(dofs_, mesh_, f, kVelocityField, tension_region(f));
    const auto real_rows = part_of(d, 0, true), imaginary_rows = part_of(d, 1, true);
    const auto real_columns = part_of(d, 0, false), imaginary_columns = part_of(d, 1, false);
    impl_->upper_blocks.push_back(
        m.add_block(std::span<const PetscInt>(real_rows), std::span<const PetscInt>(imaginary_columns)));
    impl_->lower_blocks.push_back(
        m.add_block(std::span<const PetscInt>(imaginary_rows), std::span<const PetscInt>(real_columns)));
    if (!slip_) continue;
    const auto [velocity, multipliers, constrained] = slip_face_dofs(f);
    std::array<la::CsrMatrix::Block, 2> coupling{}, constraint{};
    for (int part : {0, 1}) {
      const auto rows = part_of(velocity, part, true), columns = part_of(multipliers, part, false);
      coupling[part] = m.add_block(std::span<const PetscInt>(rows), std::span<const PetscInt>(columns));
      const auto constraint_rows = part_of(multipliers, part, true);
      const auto constraint_columns = part_of(constrained, part, false);
      constraint[part] =
          m.add_block(std::span<const PetscInt>(constraint_rows), std::span<const PetscInt>(constraint_columns));
    }
    impl_->slip_coupling_blocks.push_back(coupling);
    impl_->slip_constraint_blocks.push_back(constraint);
  }
  m.create();
}

void OscillatorySystem::create_inner_matrices() {
  const auto owned = dofs_.ownership(la::mpi_rank(), la::mpi_size());
  const la::OwnershipRange rows{owned.begin, owned.end};
  const PetscInt n = dofs_.n_dofs();
  auto& impl = *impl_;
  impl.inner = std::make_unique<la::CsrMatrix>(rows, n, rows, n);
  impl.inner_pmat = std::make_unique<la::CsrMatrix>(rows, n, rows, n);
  impl.coupling = std::make_unique<la::CsrMatrix>(rows, n, rows, n);
  auto own = [&](auto dofs) {
    std::vector<PetscInt> out(dofs.begin(), dofs.end());
    for (auto& d : out)
      if (!rows.owns(d)) d = -1;
    return out;
  };
  for (int t : assembled_tets_) {
    const auto dofs = dofs_.element_dofs(t);
    const auto r = own(dofs);
    const std::vector<PetscInt> c(dofs.begin(), dofs.end());
    impl.inner_tet_blocks.push_back(impl.inner->add_block(std::span<const PetscInt>(r), std::span<const PetscInt>(c)));
    impl.pmat_tet_blocks.push_back(
        impl.inner_pmat->add_block(std::span<const PetscInt>(r), std::span<const PetscInt>(c)));
  }
  for (int f = 0; f < n_faces(); ++f) {
    const auto d = interface_face_dofs(dofs_, mesh_, f, kVelocityField, tension_region(f));
    const auto r = own(d);
    impl.inner_face_blocks.push_back(impl.inner->add_block(std::span<const PetscInt>(r), std::span<const PetscInt>(d)));
    impl.pmat_face_blocks.push_back(
        impl.inner_pmat->add_block(std::span<const PetscInt>(r), std::span<const PetscInt>(d)));
    impl.coupling_blocks.push_back(impl.coupling->add_block(std::span<const PetscInt>(r), std::span<const PetscInt>(d)));
  }
  if (slip_) declare_inner_slip_blocks();
  impl.inner->create();
  impl.inner_pmat->create();
  impl.coupling->create();
  attach_pressure_nullspaces();

  // The inner solver: the Stokes system's iterative method (fieldsplit with
  // BoomerAMG on the velocity, the pressure mass for the Schur complement).
  std::vector<std::vector<PetscInt>> by_field(dofs_.n_fields());
  std::vector<PetscScalar> xyz;
  for (PetscInt i = rows.begin; i < rows.end; ++i) {
    const int dof = static_cast<int>(i);
    by_field[dofs_.field_of(dof)].push_back(i);
    if (dofs_.field_of(dof) == kVelocityField) xyz.push_back(mesh_.nodes[dofs_.node_of(dof)](dofs_.component_of(dof)));
  }
  std::vector<la::NamedIndexSet> fields;
  for (int f = 0; f < dofs_.n_fields(); ++f) {
    impl.field_sets.push_back(la::make_index_set(by_field[f], dofs_.field(f).components));
    fields.push_back({dofs_.field(f).name, impl.field_sets.back().get()});
  }
  if (slip_) {
    // As StokesSystem: velocity against the constraints, pressure and
    // multipliers in one Schur complement.
    std::vector<PetscInt> constraints = by_field[kPressureField];
    constraints.insert(constraints.end(), by_field[kMultiplierField].begin(),
                       by_field[kMultiplierField].end());
    std::sort(constraints.begin(), constraints.end());
    impl.field_sets.push_back(la::make_index_set(constraints));
    fields = {fields[kVelocityField], {"pressure_multiplier", impl.field_sets.back().get()}};
  }
  impl.near_nullspace = la::rigid_body_modes(xyz);
  la::SaddlePointSettings settings;
  settings.method = la::SaddlePointMethod::iterative;
  // Inexact inner solves are enough under the flexible outer method.
  // Measured (10 drops at phi = 0.2, 452k real unknowns, omega 0.4, the
  // gauge as a null space): rtol 1e-4: 9 FGMRES iterations, 39 inner
  // iterations per solve, 223 s; 3e-2: 13, 12, 110 s; 1e-2: 11, 15, 89 s;
  // the same moduli to the digits printed.
  settings.rtol = 1e-2;
  settings.max_iterations = 300;
  settings.prefix = "oscillatory_inner_";
  impl.inner_solver = std::make_unique<la::SaddlePointSolver>(settings, fields, impl.near_nullspace.get());
  // The interface nodes' velocities, solved exactly after each AMG cycle
  // where the tension's normal coupling is stiff (interface_block_pays).
  std::vector<char> on_interface(mesh_.n_nodes(), 0);
  for (const auto& tri : mesh_.interface_faces)
    for (int node : tri) on_interface[node] = 1;
  std::vector<PetscInt> interface_rows;
  PetscInt position = 0;  // among this rank's velocity unknowns
  for (PetscInt i = rows.begin; i < rows.end; ++i) {
    const int dof = static_cast<int>(i);
    if (dofs_.field_of(dof) != kVelocityField) continue;
    if (on_interface[dofs_.node_of(dof)]) interface_rows.push_back(position);
    ++position;
  }
  impl.inner_solver->set_primal_exact_block(std::move(interface_rows));
  impl.a = la::make_vector(rows.size(), n);
  for (la::Vector* v : {&impl.b, &impl.z, &impl.y, &impl.bz}) check(VecDuplicate(impl.a.get(), v->out()), "VecDuplicate");

  check(KSPCreate(PETSC_COMM_WORLD, impl.outer.out()), "KSPCreate");
  check(KSPSetOptionsPrefix(impl.outer.get(), "oscillatory_"), "KSPSetOptionsPrefix");
  check(KSPSetType(impl.outer.get(), KSPFGMRES), "KSPSetType");
  check(KSPGMRESSetRestart(impl.outer.get(), 100), "KSPGMRESSetRestart");
  check(KSPSetTolerances(impl.outer.get(), 1e-8, PETSC_DEFAULT, PETSC_DEFAULT, 300), "KSPSetTolerances");
  PC pc = nullptr;
  check(KSPGetPC(impl.outer.get(), &pc), "KSPGetPC");
  la::make_shell_preconditioner(pc, &impl, nullptr, apply_presb, nullptr, "PRESB");
}

OscillatorySystem::SlipFaceDofs OscillatorySystem::slip_face_dofs(int face) const {
  const int object = mesh_.interface_object[face];
  const auto outside = interface_face_dofs(dofs_, mesh_, face, kVelocityField, 0);
  const auto inside = interface_face_dofs(dofs_, mesh_, face, kVelocityField, object);
  const auto multipliers = interface_face_dofs(dofs_, mesh_, face, kMultiplierField, object);
  SlipFaceDofs d;
  d.velocity.assign(outside.begin(), outside.end());
  d.velocity.insert(d.velocity.end(), inside.begin(), inside.end());
  d.multipliers.assign(multipliers.begin(), multipliers.end());
  d.constrained = d.velocity;
  d.constrained.insert(d.constrained.end(), multipliers.begin(), multipliers.end());
  return d;
}

void OscillatorySystem::declare_inner_slip_blocks() {
  auto& impl = *impl_;
  const auto owned = dofs_.ownership(la::mpi_rank(), la::mpi_size());
  const la::OwnershipRange rows{owned.begin, owned.end};
  auto own = [&](std::span<const PetscInt> dofs) {
    std::vector<PetscInt> out(dofs.begin(), dofs.end());
    for (auto& d : out)
      if (!rows.owns(d)) d = -1;
    return out;
  };
  auto declare = [](la::CsrMatrix& m, std::span<const PetscInt> r, std::span<const PetscInt> c) {
    return m.add_block(r, c);
  };
  // The blocks of the real form's slip terms (create_matrix), one part's.
  for (int f = 0; f < n_faces(); ++f) {
    const auto [velocity, multipliers, constrained] = slip_face_dofs(f);
    const auto velocity_rows = own(velocity), multiplier_rows = own(multipliers);
    for (la::CsrMatrix* m : {impl.inner.get(), impl.inner_pmat.get()})
      (m == impl.inner.get() ? impl.inner_slip_blocks : impl.pmat_slip_blocks)
          .push_back(
              {declare(*m, velocity_rows, multipliers), declare(*m, multiplier_rows, constrained)});
  }
  // The preconditioner's own blocks at each owned interface node (its
  // velocity copies are owned with it: dofs are numbered node by node).
  std::vector<char> seen(mesh_.n_nodes(), 0);
  for (int f = 0; f < n_faces(); ++f) {
    const int object = mesh_.interface_object[f];
    for (int node : mesh_.interface_faces[f]) {
      if (seen[node] || !rows.owns(dofs_.dof(kMultiplierField, node, object, 0))) continue;
      seen[node] = 1;
      std::array<PetscInt, 6> copies;
      std::array<PetscInt, 3> multipliers;
      for (int c = 0; c < 3; ++c) {
        copies[c] = dofs_.dof(kVelocityField, node, 0, c);
        copies[3 + c] = dofs_.dof(kVelocityField, node, object, c);
        multipliers[c] = dofs_.dof(kMultiplierField, node, object, c);
      }
      impl.slip_nodes.push_back({node, object});
      impl.slip_node_blocks.push_back({declare(*impl.inner_pmat, copies, copies),
                                       declare(*impl.inner_pmat, multipliers, multipliers)});
    }
  }
  impl.node_scale = interface_node_scale(mesh_);
}

void OscillatorySystem::assemble_inner_slip_estimate(const OscillatoryProblem& problem) {
  // From the diagonal of K + B (assembled), as StokesSystem from A's.
  auto& impl = *impl_;
  const auto owned = dofs_.ownership(la::mpi_rank(), la::mpi_size());
  la::Vector diagonal = la::make_vector(owned.end - owned.begin, dofs_.n_dofs());
  check(MatGetDiagonal(impl.inner->get(), diagonal.get()), "MatGetDiagonal");
  const PetscScalar* a = nullptr;
  check(VecGetArrayRead(diagonal.get(), &a), "VecGetArrayRead");
  for (std::size_t i = 0; i < impl.slip_nodes.size(); ++i) {
    const auto [node, object] = impl.slip_nodes[i];
    const auto p = slip_node_preconditioner(dofs_, a, static_cast<int>(owned.begin), node, object,
                                            node_normal_[node], impl.node_scale[node],
                                            problem.slip.of(object));
    impl.inner_pmat->set_block(impl.slip_node_blocks[i][0], p.jump_penalty);
    impl.inner_pmat->set_block(impl.slip_node_blocks[i][1], p.schur_estimate);
  }
  check(VecRestoreArrayRead(diagonal.get(), &a), "VecRestoreArrayRead");
}

std::pair<la::Vector, la::Vector> OscillatorySystem::assemble(const OscillatoryProblem& problem) {
  auto& impl = *impl_;
  auto& m = *impl.matrix;
  const bool iterative = method_ == la::SaddlePointMethod::iterative;
  TetMatrix ke;
  PressureMass mass;
  for (std::size_t e = 0; e < assembled_tets_.size(); ++e) {
    const int t = assembled_tets_[e];
    ke.setZero();
    mass.setZero();
    add_stokes_tet_matrix(fem::tet_nodes(mesh_, t), tabulation_, problem.viscosity.at(mesh_.tet_region[t]), ke,
                          iterative ? &mass : nullptr);
    m.set_block(impl.real_blocks[e], ke);
    m.set_block(impl.imaginary_blocks[e], ke);
    if (iterative) {
      impl.inner->set_block(impl.inner_tet_blocks[e], ke);
      ke.bottomRightCorner<kTetPressureDofs, kTetPressureDofs>() = mass;
      impl.inner_pmat->set_block(impl.pmat_tet_blocks[e], ke);
    }
  }
  for (int i = 0; i < n_faces(); ++i) {
    const auto& tri = mesh_.interface_faces[i];
    const int object = mesh_.interface_object[i];
    const element::TriangleNodes x = fem::triangle_nodes(mesh_, tri);
    std::array<Eigen::Vector3d, 6> normals;
    for (int a = 0; a < 6; ++a) normals[a] = node_normal_[tri[a]];
    const Eigen::Matrix<double, 18, 18> b =
        linearised_tension_block(x, normals, problem.interfacial_tension[object - 1], problem.radius[object - 1]) /
        problem.omega;
    m.set_block(impl.upper_blocks[i], b);
    m.set_block(impl.lower_blocks[i], -b);
    if (slip_) {
      const auto c = slip_coupling_matrix(x, normals);
      Eigen::Matrix<double, 36, 18> coupling;
      coupling << c, -c;  // + integral lambda_h . v_m, - integral lambda_h . v_d
      const auto constraint =
          slip_constraint_block(c, surface_mass(x), normals, problem.slip.of(object));
      for (int part : {0, 1}) {
        m.set_block(impl.slip_coupling_blocks[i][part], coupling);
        m.set_block(impl.slip_constraint_blocks[i][part], constraint);
      }
      if (iterative)
        for (la::CsrMatrix* inner : {impl.inner.get(), impl.inner_pmat.get()}) {
          const auto& blocks =
              inner == impl.inner.get() ? impl.inner_slip_blocks : impl.pmat_slip_blocks;
          inner->set_block(blocks[i][0], coupling);
          inner->set_block(blocks[i][1], constraint);
        }
    }
    if (iterative) {
      impl.inner->set_block(impl.inner_face_blocks[i], b);
      // The preconditioning matrix takes B without T's -2/R^2 mass term: with
      // it, K + B is indefinite at small omega in each drop's uniform
      // expansion (the l = 0 mode, negative, only the pressure excludes it),
      // and BoomerAMG built on that broke down in the inner solves (omega =
      // 0.02, one drop on 14 equator nodes). Without it the block is
      // positive semidefinite; the operators keep the whole B, so the
      // solution is unchanged. Measured on that drop: every omega from 0.002
      // converges; at 0.4 and 4, 9 and 7 FGMRES iterations (148 and 110
      // inner) against 10 and 8 (166 and 127) with the whole B.
      impl.inner_pmat->set_block(
          impl.pmat_face_blocks[i],
          normal_surface_stiffness_block(x, normals, problem.interfacial_tension[object - 1]) /
              problem.omega);
      impl.coupling->set_block(impl.coupling_blocks[i], b);
    }
  }
  m.assemble();
  if (iterative) {
    impl.inner->assemble();
    if (slip_) assemble_inner_slip_estimate(problem);
    impl.inner_pmat->assemble();
    impl.coupling->assemble();
  }

  // Walls: the real amplitude g, the imaginary 0; the gauge's two pressures 0.
  la::Vector rhs = la::make_vector(range_.size(), n_unknowns());
  la::Vector x = la::make_vector(range_.size(), n_unknowns());
  check(VecSet(rhs.get(), 0.0), "VecSet");
  check(VecSet(x.get(), 0.0), "VecSet");
  std::vector<PetscInt> rows, inner_rows;
  std::vector<PetscScalar> values;
  std::vector<char> seen(range_.size(), 0);
  auto constrain = [&](int dof, double real_value) {
    const PetscInt row = index(dof, 0);
    if (!range_.owns(row) || seen[row - range_.begin]) return;
    seen[row - range_.begin] = 1;
    rows.insert(rows.end(), {row, row + 1});
    values.insert(values.end(), {real_value, 0.0});
    inner_rows.push_back(dof);
  };
  for (const auto& face : mesh_.boundary_faces)
    for (int node : face) {
      const Eigen::Vector3d g =
          problem.boundary_velocity ? problem.boundary_velocity(mesh_.nodes[node]) : Eigen::Vector3d::Zero();
      for (int c = 0; c < 3; ++c) constrain(dofs_.dof(kVelocityField, node, 0, c), g(c));
    }
  if (!iterative) constrain(dofs_.dof(kPressureField, problem.pressure_gauge_node, 0), 0.0);
  check(VecSetValues(x.get(), static_cast<PetscInt>(rows.size()), rows.data(), values.data(), INSERT_VALUES),
        "VecSetValues(x)");
  check(VecAssemblyBegin(x.get()), "VecAssemblyBegin");
  check(VecAssemblyEnd(x.get()), "VecAssemblyEnd");
  check(MatZeroRowsColumns(m.get(), static_cast<PetscInt>(rows.size()), rows.data(), 1.0, x.get(), rhs.get()),
        "MatZeroRowsColumns");
  if (iterative) {
    const auto n = static_cast<PetscInt>(inner_rows.size());
    check(MatZeroRowsColumns(impl.inner->get(), n, inner_rows.data(), 1.0, nullptr, nullptr), "MatZeroRowsColumns");
    check(MatZeroRowsColumns(impl.inner_pmat->get(), n, inner_rows.data(), 1.0, nullptr, nullptr),
          "MatZeroRowsColumns");
    // B has no wall or pressure rows: nothing to eliminate.
  }
  return {std::move(rhs), std::move(x)};
}

OscillatoryResponse OscillatorySystem::solve(const OscillatoryProblem& problem) {
  if (!(problem.omega > 0.0)) throw SolverError(fmt::format("OscillatoryProblem: omega = {} (must be > 0)", problem.omega));
  if (static_cast<int>(problem.viscosity.size()) < mesh_.n_objects + 1 ||
      static_cast<int>(problem.interfacial_tension.size()) < mesh_.n_objects ||
      static_cast<int>(problem.radius.size()) < mesh_.n_objects)
    throw SolverError(fmt::format("OscillatoryProblem: a viscosity per region and a tension and radius per "
                                  "object needed ({} objects)", mesh_.n_objects));
  if (problem.pressure_gauge_node < 0 || dofs_.dof(kPressureField, problem.pressure_gauge_node, 0) < 0)
    throw SolverError("OscillatoryProblem: the pressure gauge is not a matrix vertex");
  const auto start = std::chrono::steady_clock::now();
  auto [rhs, x] = assemble(problem);
  OscillatoryResponse out;
  out.assembly_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto solve_start = std::chrono::steady_clock::now();
  if (method_ == la::SaddlePointMethod::direct)
    solve_direct(problem, rhs.get(), x.get(), out);
  else
    solve_iterative(problem, rhs.get(), x.get(), out);
  out.solve.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - solve_start).count();

  const auto all = la::gather_to_all(x.get());
  const int n = dofs_.n_dofs();
  out.real.resize(n);
  out.imaginary.resize(n);
  for (int d = 0; d < n; ++d) {
    out.real[d] = all[index(d, 0)];
    out.imaginary[d] = all[index(d, 1)];
  }
  // zeta_a = u_a . n_a / (i omega)
  out.normal_displacement.assign(mesh_.n_nodes(), Complex(0.0, 0.0));
  for (const auto& s : surfaces_)
    for (int node : s.volume_node) {
      Complex un(0.0, 0.0);
      for (int c = 0; c < 3; ++c) {
        const int d = dofs_.dof(kVelocityField, node, s.object, c);  // the drop's copy
        un += Complex(out.real[d], out.imaginary[d]) * node_normal_[node](c);
      }
      out.normal_displacement[node] = un / Complex(0.0, problem.omega);
    }
  return out;
}

void OscillatorySystem::solve_direct(const OscillatoryProblem& problem, Vec rhs, Vec x, OscillatoryResponse& out) {
  auto& impl = *impl_;
  if (!impl.lu) {
    // Saddle-point LU pivots off the diagonal: room for it, as StokesSystem's.
    la::set_default_option("-oscillatory_mat_mumps_icntl_14", "80");
    impl.lu = la::lu_solver(impl.matrix->get(), "oscillatory_");
  } else {
    check(KSPSetOperators(impl.lu.get(), impl.matrix->get(), impl.matrix->get()), "KSPSetOperators");
  }
  KSP ksp = impl.lu.get();
  check(KSPSolve(ksp, rhs, x), "KSPSolve(oscillatory)");
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
  if (reason < 0) {
    PC pc = nullptr;
    check(KSPGetPC(ksp, &pc), "KSPGetPC");
    Mat factor = nullptr;
    PetscInt info = 0;
    if (PCFactorGetMatrix(pc, &factor) == 0 && factor) MatMumpsGetInfog(factor, 1, &info);
    throw SolverError(fmt::format(
        "oscillatory response at omega = {}: the LU factorisation of {} real unknowns failed ({}, MUMPS INFOG(1) "
        "= {}{}); solver.type = \"iterative\" solves without factoring the whole system",
        problem.omega, n_unknowns(), KSPConvergedReasons[reason], info,
        info == -9 || info == -8 || info == -13 ? ": out of memory or workspace" : ""));
  }
  out.solve.iterations = 1;
  out.solve.reason = KSPConvergedReasons[reason];
}

void OscillatorySystem::attach_pressure_nullspaces() {
  // Walls and periodic faces leave each part's pressure free up to one
  // constant, the same in every region; the tension acts on velocities only,
  // and the continuity rows sum to the walls' net flux (zero: they move
  // tangentially), so the constants span both null spaces of the real form
  // and, alone, those of K + B. With slip a constant pressure c loads each
  // interface with -c n on the matrix side and +c n on the drop's, which
  // the multipliers lambda_a = -c n_a (the matrix's traction) balance
  // exactly: their traction sum_a N_a (n_a . lambda_a) n is -c n, their
  // tangential parts are zero, so the constraint rows hold with u = 0.
  auto& impl = *impl_;
  const auto owned = dofs_.ownership(la::mpi_rank(), la::mpi_size());
  auto constant_pressure = [&](int dof) {
    switch (dofs_.field_of(dof)) {
      case kPressureField: return 1.0;
      case kMultiplierField: return -node_normal_[dofs_.node_of(dof)](dofs_.component_of(dof));
      default: return 0.0;
    }
  };
  la::Vector inner_constant = la::make_vector(owned.end - owned.begin, dofs_.n_dofs());
  PetscScalar* u = nullptr;
  check(VecGetArray(inner_constant.get(), &u), "VecGetArray");
  for (PetscInt d = owned.begin; d < owned.end; ++d)
    u[d - owned.begin] = constant_pressure(static_cast<int>(d));
  check(VecRestoreArray(inner_constant.get(), &u), "VecRestoreArray");
  for (int part : {0, 1}) {
    impl.pressure_constant[part] = la::make_vector(range_.size(), n_unknowns());
    PetscScalar* a = nullptr;
    check(VecGetArray(impl.pressure_constant[part].get(), &a), "VecGetArray");
    for (PetscInt d = owned.begin; d < owned.end; ++d) {
      a[index(d, 0) - range_.begin] = 0.0;
      a[index(d, 1) - range_.begin] = 0.0;
      a[index(d, part) - range_.begin] = constant_pressure(static_cast<int>(d));
    }
    check(VecRestoreArray(impl.pressure_constant[part].get(), &a), "VecRestoreArray");
  }
  const std::array<Vec, 2> outer_basis{impl.pressure_constant[0].get(),
                                       impl.pressure_constant[1].get()};
  la::attach_null_space(impl.matrix->get(), outer_basis);
  const Vec inner_basis = inner_constant.get();
  la::attach_null_space(impl.inner->get(), std::span<const Vec>(&inner_basis, 1));
}

void OscillatorySystem::solve_iterative(const OscillatoryProblem& problem, Vec rhs, Vec x,
                                        OscillatoryResponse& out) {
  auto& impl = *impl_;
  impl.inner_solver->set_operators(impl.inner->get(), impl.inner_pmat->get());
  impl.inner_solver->refactor_at_next_solve();  // a new frequency: a new matrix
  impl.inner_solver->set_primal_exact_block_active(interface_block_pays(problem, slip_));
  impl.inner_solves = impl.inner_iterations = 0;
  check(KSPSetOperators(impl.outer.get(), impl.matrix->get(), impl.matrix->get()), "KSPSetOperators");
  check(KSPSetFromOptions(impl.outer.get()), "KSPSetFromOptions");
  check(KSPSetInitialGuessNonzero(impl.outer.get(), PETSC_TRUE), "KSPSetInitialGuessNonzero");
  check(KSPSolve(impl.outer.get(), rhs, x), "KSPSolve(oscillatory, PRESB)");
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(impl.outer.get(), &reason), "KSPGetConvergedReason");
  PetscInt iterations = 0;
  check(KSPGetIterationNumber(impl.outer.get(), &iterations), "KSPGetIterationNumber");
  PetscReal residual = 0.0;
  check(KSPGetResidualNorm(impl.outer.get(), &residual), "KSPGetResidualNorm");
  if (reason < 0)
    throw SolverError(fmt::format("oscillatory response: FGMRES with PRESB did not converge ({} after {} iterations, "
                                  "{} inner Stokes solves)",
                                  KSPConvergedReasons[reason], iterations, impl.inner_solves));
  // The gauge: each part's pressure zero at the gauge vertex, as the direct path pins it.
  const PetscInt gauge = dofs_.dof(kPressureField, problem.pressure_gauge_node, 0);
  for (int part : {0, 1})
    check(VecAXPY(x, -la::entry(x, index(gauge, part)), impl.pressure_constant[part].get()), "VecAXPY");
  out.solve.iterations = static_cast<int>(iterations);
  out.solve.residual_norm = residual;
  out.solve.reason = KSPConvergedReasons[reason];
  out.inner_solves = impl.inner_solves;
  out.inner_iterations = impl.inner_iterations;
}

double OscillatorySystem::object_volume(int object) const {
  return surface_integrals(surfaces_.at(object - 1), interface_positions(surfaces_.at(object - 1), mesh_)).volume;
}

Matrix3c OscillatorySystem::stresslet(const OscillatoryProblem& problem, const OscillatoryResponse& response,
                                      int object) const {
  const double eta_m = problem.viscosity.at(0);
  const double lambda = problem.viscosity.at(object) / eta_m;
  Matrix3c volume_term = Matrix3c::Zero();  // int_V 2 D(u) dV
  for (int t = 0; t < mesh_.n_tets(); ++t) {
    if (mesh_.tet_region[t] != object) continue;
    const auto x = fem::tet_nodes(mesh_, t);
    const auto dofs = dofs_.element_dofs(t);  // velocity first, 3 k + i
    for (int q = 0; q < tabulation_.rule.size(); ++q) {
      const auto map = element::tet_map(x, tabulation_.p2_grad[q]);
      const Eigen::Matrix<double, 10, 3> grad = element::physical_gradients<10>(tabulation_.p2_grad[q], map);
      Matrix3c velocity_gradient = Matrix3c::Zero();  // du_i / dx_j
      for (int k = 0; k < 10; ++k)
        for (int i = 0; i < 3; ++i) {
          const int d = dofs[3 * k + i];
          const Complex u(response.real[d], response.imaginary[d]);
          for (int j = 0; j < 3; ++j) velocity_gradient(i, j) += u * grad(k, j);
        }
      const double w = tabulation_.rule.weights[q] * map.det_jacobian;
      volume_term += w * (velocity_gradient + velocity_gradient.transpose());
    }
  }
  // delta int_S n n ds and, with slip, int_S [(u_d - u_m) n + n (u_d - u_m)] ds,
  // on the outward-oriented interface.
  static const element::QuadratureRule rule = element::triangle_rule(5);
  const auto& surface = surfaces_.at(object - 1);
  const double radius = problem.radius.at(object - 1);
  Matrix3c tension_change = Matrix3c::Zero(), slip_term = Matrix3c::Zero();
  auto amplitude = [&](int dof) { return Complex(response.real[dof], response.imaginary[dof]); };
  for (const auto& tri : surface.triangles) {
    element::TriangleNodes x;
    std::array<Complex, 6> zeta;
    std::array<Eigen::Vector3cd, 6> jump;  // u_d - u_m at the nodes
    for (int a = 0; a < 6; ++a) {
      const int node = surface.volume_node[tri[a]];
      x.col(a) = mesh_.nodes[node];
      zeta[a] = response.normal_displacement[node];
      for (int c = 0; c < 3; ++c)
        jump[a](c) = slip_ ? amplitude(dofs_.dof(kVelocityField, node, object, c)) -
                                 amplitude(dofs_.dof(kVelocityField, node, 0, c))
                           : Complex(0.0, 0.0);
    }
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(x, rule.points[q]);
      const auto values = element::p2_triangle_values(rule.points[q]);
      Complex z(0.0, 0.0);
      Eigen::Vector3cd grad_z = Eigen::Vector3cd::Zero(), u_jump = Eigen::Vector3cd::Zero();
      for (int a = 0; a < 6; ++a) {
        z += values[a] * zeta[a];
        grad_z += zeta[a] * p.surface_gradients.row(a).transpose().cast<Complex>();
        u_jump += values[a] * jump[a];
      }
      const Eigen::Vector3cd n = p.normal.cast<Complex>();
      const double w = rule.weights[q] * p.area_scale;
      tension_change += w * (-(grad_z * n.transpose()) - n * grad_z.transpose() + (2.0 / radius) * z * (n * n.transpose()));
      if (slip_) slip_term += w * (u_jump * n.transpose() + n * u_jump.transpose());
    }
  }
  const double gamma = problem.interfacial_tension.at(object - 1);
  const Complex trace_third = tension_change.trace() / 3.0;
  return (lambda - 1.0) * eta_m * volume_term - gamma * (tension_change - trace_third * Matrix3c::Identity()) +
         eta_m * slip_term;
}

}  // namespace softflow::physics
