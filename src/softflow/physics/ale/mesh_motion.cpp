#include "softflow/physics/ale/mesh_motion.hpp"

#include <algorithm>
#include <chrono>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/fem/dof_map.hpp"
#include "softflow/la/csr_matrix.hpp"
#include "softflow/la/saddle_point_solver.hpp"  // la::set_default_option
#include "softflow/la/vector_values.hpp"
#include "softflow/mesh/half_turn.hpp"
#include "softflow/mesh/quality.hpp"

namespace softflow::physics {

namespace {
using la::check;
using Clock = std::chrono::steady_clock;

// Degree 5 (14 points), as the Stokes assembly: exact on straight P2
// elements (integrand of degree 2) and accurate on curved ones.
constexpr int kQuadratureDegree = 5;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

enum NodeKind : signed char { kUnused = -1, kFree = 0, kInterface = 1, kOuter = 2 };
}  // namespace

double ale_tet_matrix(const element::TetNodes& x, const fem::TetTabulation& tab,
                      AleTetMatrix& out) {
  out.setZero();
  double volume = 0.0;
  for (int q = 0; q < tab.rule.size(); ++q) {
    const auto map = element::tet_map(x, tab.p2_grad[q]);
    if (!(map.det_jacobian > 0.0))
      throw SolverError(
          fmt::format("ALE mesh motion: non-positive Jacobian ({:.3e}) in a reference element",
                      map.det_jacobian));
    const Eigen::Matrix<double, 10, 3> g = element::physical_gradients<10>(tab.p2_grad[q], map);
    const double w = tab.rule.weights[q] * map.det_jacobian;
    out.noalias() += w * (g * g.transpose());
    volume += w;
  }
  out /= volume;  // k_e = 1 / V_e
  return volume;
}

AleMeshMotion::AleMeshMotion(const mesh::Mesh& reference, const AleSettings& settings)
    : settings_(settings), n_nodes_(reference.n_nodes()) {
  partition(reference);
  const auto start = Clock::now();
  assemble(reference);
  assembly_seconds_ = seconds_since(start);
  create_solver();
}

AleMeshMotion::~AleMeshMotion() = default;

void AleMeshMotion::partition(const mesh::Mesh& mesh) {
  const int n = mesh.n_nodes();
  master_.resize(n);
  for (int i = 0; i < n; ++i) master_[i] = mesh.master(i);

  // Classify representative nodes. Interface wins over the outer boundary.
  std::vector<signed char> kind(n, kUnused);
  for (const auto& tet : mesh.tets)
    for (int node : tet) kind[master_[node]] = kFree;
  for (const auto& face : mesh.boundary_faces)
    for (int node : face) kind[master_[node]] = kOuter;
  interface_source_.assign(n, -1);
  std::vector<char> on_interface(n, 0);
  for (const auto& face : mesh.interface_faces)
    for (int node : face) {
      on_interface[node] = 1;
      const int rep = master_[node];
      kind[rep] = kInterface;
      if (interface_source_[rep] < 0) interface_source_[rep] = node;
    }
  for (int i = 0; i < n; ++i)
    if (on_interface[i]) interface_nodes_.push_back(i);

  // Numbering in representative-node order: contiguous node ranges give
  // contiguous ranges of free and of interface unknowns.
  std::vector<int> free_before(n + 1, 0), interface_before(n + 1, 0);
  for (int i = 0; i < n; ++i) {
    free_before[i + 1] = free_before[i] + (kind[i] == kFree);
    interface_before[i + 1] = interface_before[i] + (kind[i] == kInterface);
  }
  n_free_ = free_before[n];
  n_interface_ = interface_before[n];
  free_index_.assign(n, -1);
  interface_index_.assign(n, -1);
  for (int i = 0; i < n; ++i) {
    if (kind[i] == kFree) free_index_[i] = free_before[i];
    if (kind[i] == kInterface) interface_index_[i] = interface_before[i];
  }

  // This rank's node range, as every dof map's (fem::rank_node_range).
  const auto [node_begin, node_end] = fem::rank_node_range(n, la::mpi_rank(), la::mpi_size());
  free_range_ = {free_before[node_begin], free_before[node_end]};
  interface_range_ = {interface_before[node_begin], interface_before[node_end]};

  for (int t = 0; t < mesh.n_tets(); ++t) {
    const int rep = master_[mesh.tets[t][0]];
    if (rep >= node_begin && rep < node_end) owned_tets_.push_back(t);
  }
  for (int i = node_begin; i < node_end; ++i)
    if (kind[i] == kInterface) owned_interface_source_.push_back(interface_source_[i]);
}

void AleMeshMotion::assemble(const mesh::Mesh& mesh) {
  // One element matrix feeds two blocks of the operator: the free-free
  // block A (rows and columns free) and the coupling block C (rows free,
  // columns prescribed on the interface). Each block's index lists carry -1
  // for the other kind of node, which la::CsrMatrix drops.
  la::CsrMatrix a(free_range_, n_free_, free_range_, n_free_);
  la::CsrMatrix c(free_range_, n_free_, interface_range_, n_interface_);
  const bool has_coupling = n_interface_ > 0;
  std::array<PetscInt, 10> rows{}, interface_columns{};
  auto element_indices = [&](int t) {
    for (int k = 0; k < 10; ++k) {
      const int rep = master_[mesh.tets[t][k]];
      rows[k] = free_index_[rep];
      interface_columns[k] = interface_index_[rep];
    }
  };
  std::vector<la::CsrMatrix::Block> blocks;
  for (int t : owned_tets_) {
    element_indices(t);
    blocks.push_back(a.add_block(std::span<const PetscInt>(rows), std::span<const PetscInt>(rows)));
    if (has_coupling)
      c.add_block(std::span<const PetscInt>(rows), std::span<const PetscInt>(interface_columns));
  }
  a.create();
  if (has_coupling) c.create();

  const fem::TetTabulation tab(kQuadratureDegree);
  AleTetMatrix ke;
  for (std::size_t e = 0; e < owned_tets_.size(); ++e) {
    ale_tet_matrix(fem::tet_nodes(mesh, owned_tets_[e]), tab, ke);
    a.set_block(blocks[e], ke);
    if (has_coupling) c.set_block(blocks[e], ke);  // same declaration order, same offsets
  }
  a.assemble();
  if (has_coupling) c.assemble();
  a_ = a.release();
  if (has_coupling) coupling_ = c.release();
  check(MatSetOption(a_.get(), MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption(symmetric)");
  check(MatSetOption(a_.get(), MAT_SPD, PETSC_TRUE), "MatSetOption(spd)");
}

void AleMeshMotion::create_solver() {
  method_ = settings_.method;
  if (method_ == AleMethod::automatic)
    method_ = n_free_ <= kAleDirectLimit ? AleMethod::direct : AleMethod::iterative;

  rhs_ = la::make_vector(free_range_.size(), n_free_);
  for (auto& x : solution_) {
    x = la::make_vector(free_range_.size(), n_free_);
    check(VecSet(x.get(), 0.0), "VecSet");
  }
  interface_values_ = la::make_vector(interface_range_.size(), n_interface_);
  check(VecScatterCreateToAll(rhs_.get(), to_all_.out(), gathered_.out()), "VecScatterCreateToAll");
  if (n_free_ == 0) return;

  const auto start = Clock::now();
  check(KSPCreate(PETSC_COMM_WORLD, ksp_.out()), "KSPCreate");
  check(KSPSetOptionsPrefix(ksp_.get(), settings_.prefix.c_str()), "KSPSetOptionsPrefix");
  check(KSPSetOperators(ksp_.get(), a_.get(), a_.get()), "KSPSetOperators");
  PC pc = nullptr;
  check(KSPGetPC(ksp_.get(), &pc), "KSPGetPC");
  const std::string p = "-" + settings_.prefix;
  if (method_ == AleMethod::direct) {
    check(KSPSetType(ksp_.get(), KSPPREONLY), "KSPSetType");
    check(PCSetType(pc, PCCHOLESKY), "PCSetType");
    check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
    for (la::Matrix* m : {&rhs_block_, &solution_block_})
      check(MatCreateDense(PETSC_COMM_WORLD, free_range_.size(), PETSC_DECIDE, n_free_, 3, nullptr,
                           m->out()),
            "MatCreateDense");
  } else {
    check(KSPSetType(ksp_.get(), KSPCG), "KSPSetType");
    // A true-residual test: independent of the preconditioner's scaling.
    check(KSPSetNormType(ksp_.get(), KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
    check(
        KSPSetTolerances(ksp_.get(), settings_.rtol, 0.0, PETSC_DEFAULT, settings_.max_iterations),
        "KSPSetTolerances");
    // Warm start: each component starts from its previous solution, which
    // is close when successive interface increments are (time stepping).
    check(KSPSetInitialGuessNonzero(ksp_.get(), PETSC_TRUE), "KSPSetInitialGuessNonzero");
    check(PCSetType(pc, PCHYPRE), "PCSetType");
    check(PCHYPRESetType(pc, "boomeramg"), "PCHYPRESetType");
    // Measured on gmsh drop meshes (README.md): a low strong threshold
    // without aggressive coarsening halves the iterations of the
    // Stokes-velocity settings (0.7, agg_nl 1) and wins in solve time.
    la::set_default_option(p + "pc_hypre_boomeramg_strong_threshold", "0.25");
    la::set_default_option(p + "pc_hypre_boomeramg_coarsen_type", "HMIS");
    la::set_default_option(p + "pc_hypre_boomeramg_interp_type", "ext+i");
    la::set_default_option(p + "pc_hypre_boomeramg_P_max", "4");
  }
  check(KSPSetFromOptions(ksp_.get()), "KSPSetFromOptions");
  check(KSPSetUp(ksp_.get()), "KSPSetUp");
  setup_seconds_ = seconds_since(start);
}

void AleMeshMotion::interface_rhs(const std::vector<Eigen::Vector3d>& d_s, int c, Vec b) {
  // b = -C d_S: the eliminated interface columns.
  if (n_interface_ == 0) {
    check(VecSet(b, 0.0), "VecSet");
    return;
  }
  PetscScalar* g = nullptr;
  check(VecGetArray(interface_values_.get(), &g), "VecGetArray");
  for (std::size_t i = 0; i < owned_interface_source_.size(); ++i)
    g[i] = d_s[owned_interface_source_[i]](c);
  check(VecRestoreArray(interface_values_.get(), &g), "VecRestoreArray");
  check(MatMult(coupling_.get(), interface_values_.get(), b), "MatMult(C)");
  check(VecScale(b, -1.0), "VecScale");
}

void AleMeshMotion::solve_iterative(const std::vector<Eigen::Vector3d>& d_s, int c) {
  interface_rhs(d_s, c, rhs_.get());
  Vec x = solution_[c].get();
  PetscReal b_norm = 0.0;
  check(VecNorm(rhs_.get(), NORM_2, &b_norm), "VecNorm");
  if (b_norm == 0.0) {
    // The answer is exactly zero; a warm-started CG could not reach a
    // relative tolerance of a zero right-hand side.
    check(VecSet(x, 0.0), "VecSet");
    last_iterations_[c] = 0;
    return;
  }
  check(KSPSolve(ksp_.get(), rhs_.get(), x), "KSPSolve(ALE)");
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(ksp_.get(), &reason), "KSPGetConvergedReason");
  PetscInt its = 0;
  check(KSPGetIterationNumber(ksp_.get(), &its), "KSPGetIterationNumber");
  last_iterations_[c] = static_cast<int>(its);
  if (reason < 0) {
    PetscReal rnorm = 0.0;
    KSPGetResidualNorm(ksp_.get(), &rnorm);
    throw SolverError(
        fmt::format("ALE mesh motion: CG did not converge (component {}): {} after {} iterations "
                    "(residual {:.3e} of {:.3e}); try -{}pc_type gamg or AleMethod::direct",
                    c, KSPConvergedReasons[reason], its, rnorm, b_norm, settings_.prefix));
  }
}

void AleMeshMotion::solve_direct(const std::vector<Eigen::Vector3d>& d_s) {
  // The three components as one block right-hand side: the factor is read
  // once per call instead of three times.
  for (int c = 0; c < 3; ++c) {
    Vec b = nullptr;
    check(MatDenseGetColumnVecWrite(rhs_block_.get(), c, &b), "MatDenseGetColumnVecWrite");
    interface_rhs(d_s, c, b);
    check(MatDenseRestoreColumnVecWrite(rhs_block_.get(), c, &b), "MatDenseRestoreColumnVecWrite");
  }
  check(KSPMatSolve(ksp_.get(), rhs_block_.get(), solution_block_.get()), "KSPMatSolve(ALE)");
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(ksp_.get(), &reason), "KSPGetConvergedReason");
  if (reason < 0)
    throw SolverError(
        fmt::format("ALE mesh motion: Cholesky solve failed: {}", KSPConvergedReasons[reason]));
  for (int c = 0; c < 3; ++c) {
    Vec x = nullptr;
    check(MatDenseGetColumnVecRead(solution_block_.get(), c, &x), "MatDenseGetColumnVecRead");
    check(VecCopy(x, solution_[c].get()), "VecCopy");
    check(MatDenseRestoreColumnVecRead(solution_block_.get(), c, &x),
          "MatDenseRestoreColumnVecRead");
  }
  last_iterations_ = {1, 1, 1};
}

void AleMeshMotion::save_warm_start(StateRecord& record, const std::string& prefix) const {
  if (method_ != AleMethod::iterative) return;
  for (int c = 0; c < 3; ++c)
    la::save_vector(record, fmt::format("{}warm_start_{}", prefix, c), solution_[c].get());
}

void AleMeshMotion::restore_warm_start(const StateRecord& record, const std::string& prefix) {
  if (method_ != AleMethod::iterative || !record.contains(prefix + "warm_start_0")) return;
  for (int c = 0; c < 3; ++c)
    la::restore_vector(record, fmt::format("{}warm_start_{}", prefix, c), solution_[c].get(),
                       "ALE warm start");
}

std::vector<Eigen::Vector3d> AleMeshMotion::solve(
    const std::vector<Eigen::Vector3d>& interface_displacement) {
  if (static_cast<int>(interface_displacement.size()) != n_nodes_)
    throw SolverError(fmt::format("ALE mesh motion: {} displacements for {} mesh nodes",
                                  interface_displacement.size(), n_nodes_));
  const auto start = Clock::now();
  last_iterations_ = {0, 0, 0};
  std::vector<Eigen::Vector3d> d(n_nodes_, Eigen::Vector3d::Zero());
  if (n_free_ > 0) {
    if (method_ == AleMethod::direct) {
      solve_direct(interface_displacement);
    } else {
      for (int c = 0; c < 3; ++c) solve_iterative(interface_displacement, c);
    }
    for (int c = 0; c < 3; ++c) {
      Vec x = solution_[c].get();
      check(VecScatterBegin(to_all_.get(), x, gathered_.get(), INSERT_VALUES, SCATTER_FORWARD),
            "VecScatterBegin");
      check(VecScatterEnd(to_all_.get(), x, gathered_.get(), INSERT_VALUES, SCATTER_FORWARD),
            "VecScatterEnd");
      const PetscScalar* all = nullptr;
      check(VecGetArrayRead(gathered_.get(), &all), "VecGetArrayRead");
      for (int i = 0; i < n_nodes_; ++i) {
        const int f = free_index_[master_[i]];
        if (f >= 0) d[i](c) = all[f];
      }
      check(VecRestoreArrayRead(gathered_.get(), &all), "VecRestoreArrayRead");
    }
  }
  for (int i = 0; i < n_nodes_; ++i) {
    const int source = interface_source_[master_[i]];
    if (source >= 0) d[i] = interface_displacement[source];
  }
  last_solve_seconds_ = seconds_since(start);
  return d;
}

namespace {

/// The mesh motion's extension (eq. 2.55) of `interface` (indexed by mesh
/// node, read at the interface nodes), factored: used once per run, and the
/// objects' interiors come out as their data to round-off, where CG would
/// leave them so to its tolerance.
std::vector<Eigen::Vector3d> extend_once(const mesh::Mesh& mesh,
                                         const std::vector<Eigen::Vector3d>& interface) {
  AleSettings settings;
  settings.method = AleMethod::direct;
  AleMeshMotion motion(mesh, settings);
  std::vector<Eigen::Vector3d> d(mesh.n_nodes(), Eigen::Vector3d::Zero());
  for (int node : motion.interface_nodes()) d[node] = interface[node];
  return motion.solve(d);
}

/// Moves every node of `mesh` by `displacement`; throws MeshError with
/// `inverted(element)` if an element inverts.
template <class Message>
void move_nodes(mesh::Mesh& mesh, const std::vector<Eigen::Vector3d>& displacement,
                const Message& inverted) {
  for (int i = 0; i < mesh.n_nodes(); ++i) mesh.nodes[i] += displacement[i];
  const int worst = mesh::worst_tet(mesh);
  if (!(mesh::tet_quality(mesh, worst) > 0.0))
    throw MeshError(inverted(mesh::describe_element(mesh, worst)));
}

/// The most steps carry_objects divides an offset into.
constexpr int kMostCarrySteps = 16;

/// One rigid carry of the objects by `step` (of the whole `offset`, which
/// the message names), the displacement made exactly equivariant on a
/// point-symmetric mesh.
void carry_step(mesh::Mesh& mesh, const Eigen::Vector3d& step, const Eigen::Vector3d& offset) {
  std::vector<Eigen::Vector3d> displacement =
      extend_once(mesh, std::vector<Eigen::Vector3d>(mesh.n_nodes(), step));
  // On a point-symmetric mesh the extension is equivariant only to the
  // solver's round-off; averaged with its image (the mirror case's
  // displacement is -R of it) it is so to the bit, so that the mirror
  // case's mesh is this one's image to the bit and a run's discrete choices
  // (node relocation's comparisons) come out mirrored.
  if (const std::vector<int> image = mesh::half_turn_images(mesh); !image.empty()) {
    const std::vector<Eigen::Vector3d> solved = displacement;
    for (int i = 0; i < mesh.n_nodes(); ++i)
      displacement[i] = 0.5 * (solved[i] - mesh::half_turn(solved[image[i]]));
  }
  move_nodes(mesh, displacement, [&](const std::string& element) {
    return fmt::format(
        "mesh.point_symmetric_start: carrying the object by ({:g}, {:g}, {:g}) from the z axis "
        "to its centre inverts an element ({}), even in {} steps: the offset is too large for "
        "the elements between the object and the wall; move the object nearer the centre plane, "
        "refine the mesh there (mesh.wall_size, mesh.growth), or set "
        "mesh.point_symmetric_start = false",
        offset.x(), offset.y(), offset.z(), element, kMostCarrySteps);
  });
}

/// carry_objects without the mirror rule; `asked`: the offset the message names.
int carry_in_steps(mesh::Mesh& mesh, const Eigen::Vector3d& offset, const Eigen::Vector3d& asked) {
  // The whole offset in one extension, as every carry that succeeds so
  // takes it. Where that inverts an element the offset is taken in 2, 4,
  // ... 16 equal steps, each extended on the mesh the one before left:
  // k_e = 1 / V_e (eq. 2.55) then stiffens the elements already squeezed
  // between the object and the wall, and the next step moves them less.
  const mesh::Mesh start = mesh;
  for (int steps = 1;; steps *= 2) {
    try {
      for (int s = 0; s < steps; ++s) carry_step(mesh, offset / steps, asked);
      return steps;
    } catch (const MeshError&) {
      if (steps >= kMostCarrySteps) throw;
      mesh = start;
    }
  }
}

}  // namespace

int carry_objects(mesh::Mesh& mesh, const Eigen::Vector3d& offset) {
  // After a first step the carried mesh has no symmetry of its own, and the
  // solves of a case and of its mirror image (the same systems with the
  // nodes renumbered) agree only to round-off. So on a point-symmetric mesh
  // the offsets pointing down (and, in the centre plane, towards -x) are
  // carried as the image of the carry up, R d(-offset) with R the half turn,
  // which keeps mirror cases each other's images to the bit in any number
  // of steps (in one step the two coincide to the bit anyway).
  if (offset.z() == 0.0 && (offset.y() < 0.0 || (offset.y() == 0.0 && offset.x() < 0.0))) {
    if (const std::vector<int> image = mesh::half_turn_images(mesh); !image.empty()) {
      mesh::Mesh up = mesh;
      const int steps = carry_in_steps(up, -offset, offset);
      for (int i = 0; i < mesh.n_nodes(); ++i) mesh.nodes[i] = mesh::half_turn(up.nodes[image[i]]);
      return steps;
    }
  }
  return carry_in_steps(mesh, offset, offset);
}

void deform_objects(mesh::Mesh& mesh, const std::vector<ObjectDeformation>& deformations) {
  if (deformations.empty()) return;
  // The object of every node inside or on an object (0: liquid only).
  std::vector<int> node_object(mesh.n_nodes(), 0);
  for (int t = 0; t < mesh.n_tets(); ++t)
    if (mesh.tet_region[t] > 0)
      for (int node : mesh.tets[t]) node_object[node] = mesh.tet_region[t];
  std::vector<Eigen::Vector3d> exact(mesh.n_nodes(), Eigen::Vector3d::Zero());
  std::vector<bool> moved(mesh.n_nodes(), false);
  for (const ObjectDeformation& f : deformations)
    for (int i = 0; i < mesh.n_nodes(); ++i)
      if (node_object[i] == f.object) {
        exact[i] = (f.map - Eigen::Matrix3d::Identity()) * (mesh.nodes[i] - f.centre);
        moved[i] = true;
      }
  std::vector<Eigen::Vector3d> displacement = extend_once(mesh, exact);
  // The extension of linear data is not linear where the stiffness varies:
  // the objects' own nodes take the map itself.
  for (int i = 0; i < mesh.n_nodes(); ++i)
    if (moved[i]) displacement[i] = exact[i];
  move_nodes(mesh, displacement, [](const std::string& element) {
    return fmt::format(
        "objects[].initial_deformation: deforming the objects' meshes into their start shapes "
        "inverts an element ({}): the deformation is too large for the elements around the "
        "object; refine the mesh there (mesh.equator_nodes, mesh.growth) or start from the "
        "sphere (initial_deformation = \"none\")",
        element);
  });
}

}  // namespace softflow::physics
