#include "softflow/physics/stokes/stokes_system.hpp"

#include <algorithm>
#include <chrono>
#include <limits>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/physics/stokes/stokes_kernels.hpp"

namespace softflow::physics {

namespace {
using la::check;
// Degree 5 (14 points): exact for the affine-element integrands (degree <= 4)
// and accurate to well below discretisation error on curved P2 elements.
constexpr int kQuadratureDegree = 5;
}  // namespace

StokesSystem::StokesSystem(const mesh::Mesh& mesh, const la::SaddlePointSettings& settings,
                           bool double_interface_velocity)
    : mesh_(mesh),
      settings_(settings),
      dofs_(mesh, double_interface_velocity),
      tabulation_(kQuadratureDegree) {
  partition();
  create_matrices();
  solver_ = std::make_unique<la::SaddlePointSolver>(settings_, velocity_is_.get(),
                                                    pressure_is_.get());
}

StokesSystem::~StokesSystem() = default;

void StokesSystem::partition() {
  // Contiguous node ranges with about equal numbers of unknowns per rank.
  const int rank = la::mpi_rank(), size = la::mpi_size();
  const int n_nodes = mesh_.n_nodes();
  const long target_begin = static_cast<long>(dofs_.n_dofs()) * rank / size;
  const long target_end = static_cast<long>(dofs_.n_dofs()) * (rank + 1) / size;
  auto first_node_at = [&](long dof) {
    int lo = 0, hi = n_nodes;  // first node whose offset >= dof
    while (lo < hi) {
      const int mid = (lo + hi) / 2;
      if (dofs_.dof_offset_of_node(mid) < dof) lo = mid + 1; else hi = mid;
    }
    return lo;
  };
  range_.begin = dofs_.dof_offset_of_node(first_node_at(target_begin));
  range_.end = rank + 1 == size ? dofs_.n_dofs() : dofs_.dof_offset_of_node(first_node_at(target_end));

  for (int t = 0; t < mesh_.n_tets(); ++t)
    if (range_.owns(dofs_.tet_dofs(t)[0])) owned_tets_.push_back(t);
  for (int f = 0; f < static_cast<int>(mesh_.interface_faces.size()); ++f) {
    const int node = mesh_.interface_faces[f][0];
    if (range_.owns(dofs_.velocity_dof(node, 0))) owned_interface_faces_.push_back(f);
  }

  std::vector<PetscInt> velocity, pressure;
  for (PetscInt i = range_.begin; i < range_.end; ++i)
    (dofs_.is_velocity(static_cast<int>(i)) ? velocity : pressure).push_back(i);
  velocity_is_ = la::make_index_set(velocity, 3);
  pressure_is_ = la::make_index_set(pressure);
}

void StokesSystem::create_matrices() {
  // Coordinate-format assembly: the (row, column) list of every element
  // entry is handed to PETSc once; each later assembly passes only the
  // values, in the same order. PETSc then sums repeated entries and routes
  // off-rank rows itself. MatSetValues, by contrast, searches every row for
  // every entry and cost ~40 ns an entry: 5x the element kernels.
  // The interface blocks of the semi-implicit tension are always in the
  // pattern (zero when it is off), so that one pattern serves every solve.
  const std::size_t n = owned_tets_.size() * kTetMatrixSize +
                        owned_interface_faces_.size() * kInterfaceMatrixSize;
  auto make = [&](la::Matrix& m) {
    std::vector<PetscInt> rows(n), cols(n);  // PETSc may reorder them
    std::size_t e = 0;
    for (int t : owned_tets_) {
      const auto& d = dofs_.tet_dofs(t);
      for (int i = 0; i < 34; ++i)
        for (int j = 0; j < 34; ++j, ++e) {
          rows[e] = d[i];
          cols[e] = d[j];
        }
    }
    for (int f : owned_interface_faces_) {
      const auto d = interface_velocity_dofs(f);
      for (int i = 0; i < 18; ++i)
        for (int j = 0; j < 18; ++j, ++e) {
          rows[e] = d[i];
          cols[e] = d[j];
        }
    }
    check(MatCreate(PETSC_COMM_WORLD, m.out()), "MatCreate");
    check(MatSetSizes(m.get(), range_.size(), range_.size(), dofs_.n_dofs(), dofs_.n_dofs()),
          "MatSetSizes");
    check(MatSetType(m.get(), MATAIJ), "MatSetType");
    check(MatSetPreallocationCOO(m.get(), static_cast<PetscCount>(n), rows.data(), cols.data()),
          "MatSetPreallocationCOO");
  };
  make(a_);
  values_.resize(n);
  if (settings_.method == la::SaddlePointMethod::iterative) {
    make(pmat_);
    preconditioner_values_.resize(n);
  }
}

void StokesSystem::assemble(const StokesProblem& problem, Vec rhs) {
  const bool iterative = static_cast<bool>(pmat_);
  TetMatrix ke;
  TetVector fe;
  for (std::size_t e = 0; e < owned_tets_.size(); ++e) {
    const int t = owned_tets_[e];
    const int region = mesh_.tet_region[t];
    const double eta = problem.viscosity.at(region);
    const auto x = fem::tet_nodes(mesh_, t);
    const auto& d = dofs_.tet_dofs(t);
    ke.setZero();
    PressureMass mass = PressureMass::Zero();
    add_stokes_tet_matrix(x, tabulation_, eta, ke, iterative ? &mass : nullptr);
    // Eigen is column-major; the element matrix is symmetric, so its data is
    // also the row-major order of the coordinate list.
    std::copy(ke.data(), ke.data() + kTetMatrixSize, values_.begin() + e * kTetMatrixSize);
    if (iterative) {
      ke.bottomRightCorner<4, 4>() = mass;
      std::copy(ke.data(), ke.data() + kTetMatrixSize,
                preconditioner_values_.begin() + e * kTetMatrixSize);
    }
    if (problem.body_force) {
      fe.setZero();
      add_body_force(x, tabulation_, [&](const Vec3& xq) { return problem.body_force(xq, region); },
                     fe);
      check(VecSetValues(rhs, 30, d.data(), fe.data(), ADD_VALUES), "VecSetValues(f)");
    }
  }
  const auto& implicit = problem.semi_implicit_tension;
  std::size_t e = owned_tets_.size() * kTetMatrixSize;
  for (std::size_t i = 0; i < owned_interface_faces_.size(); ++i, e += kInterfaceMatrixSize) {
    const int f = owned_interface_faces_[i];
    const int object = mesh_.interface_object[f];
    const double gamma = object - 1 < static_cast<int>(problem.interfacial_tension.size())
                             ? problem.interfacial_tension[object - 1]
                             : 0.0;
    InterfaceMatrix block = InterfaceMatrix::Zero();
    if (gamma != 0.0) {
      const auto& tri = mesh_.interface_faces[f];
      const auto x = fem::triangle_nodes(mesh_, tri);
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
      const auto rows = interface_velocity_dofs(f);
      check(VecSetValues(rhs, 18, rows.data(), fs.data(), ADD_VALUES), "VecSetValues(tension)");
    }
    // Symmetric, so column-major data is also the coordinate list's row-major order.
    std::copy(block.data(), block.data() + kInterfaceMatrixSize, values_.begin() + e);
    if (iterative)
      std::copy(block.data(), block.data() + kInterfaceMatrixSize,
                preconditioner_values_.begin() + e);
  }
  check(MatSetValuesCOO(a_.get(), values_.data(), INSERT_VALUES), "MatSetValuesCOO(A)");
  if (iterative)
    check(MatSetValuesCOO(pmat_.get(), preconditioner_values_.data(), INSERT_VALUES),
          "MatSetValuesCOO(P)");
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
      const int v = dofs_.first_velocity_dof(node);
      for (int c = 0; c < 3; ++c) constrain(v + c, g(c));
    }
  if (problem.pressure_gauge_node >= 0) {
    const int p = dofs_.pressure_dof(problem.pressure_gauge_node, 0);
    if (p < 0) throw SolverError("pressure gauge node is not a matrix vertex");
    constrain(p, problem.pressure_gauge_value);
  }
  check(VecSetValues(x, static_cast<PetscInt>(rows.size()), rows.data(), values.data(),
                     INSERT_VALUES),
        "VecSetValues(x)");
  check(VecAssemblyBegin(x), "VecAssemblyBegin");
  check(VecAssemblyEnd(x), "VecAssemblyEnd");
  for (Mat m : {a_.get(), pmat_.get()}) {
    if (!m) continue;
    const bool is_operator = m == a_.get();
    check(MatZeroRowsColumns(m, static_cast<PetscInt>(rows.size()), rows.data(), 1.0,
                             is_operator ? x : nullptr, is_operator ? rhs : nullptr),
          "MatZeroRowsColumns");
  }
}

StokesResult StokesSystem::solve(const StokesProblem& problem) {
  if (problem.semi_implicit_tension.active() &&
      (static_cast<int>(problem.semi_implicit_tension.node_normal.size()) < mesh_.n_nodes() ||
       static_cast<int>(problem.semi_implicit_tension.predicted_normal_velocity.size()) <
           mesh_.n_nodes()))
    throw SolverError("StokesProblem: semi-implicit tension needs a normal and a normal "
                      "velocity for every mesh node");
  if (static_cast<int>(problem.viscosity.size()) < mesh_.n_objects + 1)
    throw SolverError(fmt::format("StokesProblem: {} viscosities for {} regions",
                                  problem.viscosity.size(), mesh_.n_objects + 1));
  const auto start = std::chrono::steady_clock::now();
  la::Vector rhs = la::make_vector(range_.size(), dofs_.n_dofs());
  la::Vector x = la::make_vector(range_.size(), dofs_.n_dofs());
  check(VecSet(rhs.get(), 0.0), "VecSet");
  check(VecSet(x.get(), 0.0), "VecSet");
  assemble(problem, rhs.get());
  apply_dirichlet(problem, rhs.get(), x.get());
  StokesResult result;
  result.assembly_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  solver_->set_operators(a_.get(), pmat_.get());
  result.solve = solver_->solve(rhs.get(), x.get());
  result.solution = la::gather_to_all(x.get());
  return result;
}

std::array<PetscInt, 18> StokesSystem::interface_velocity_dofs(int face) const {
  // Shared (no-slip) velocity: the matrix-side copy is the interface velocity.
  const auto& tri = mesh_.interface_faces[face];
  std::array<PetscInt, 18> rows;
  for (int k = 0; k < 6; ++k)
    for (int c = 0; c < 3; ++c) rows[3 * k + c] = dofs_.velocity_dof(tri[k], 0) + c;
  return rows;
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
