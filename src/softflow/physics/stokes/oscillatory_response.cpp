#include "softflow/physics/stokes/oscillatory_response.hpp"

#include <chrono>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/fem/field.hpp"
#include "softflow/la/csr_matrix.hpp"
#include "softflow/la/vector_values.hpp"
#include "softflow/physics/stokes/interface_slip.hpp"
#include "softflow/physics/stokes/stokes_kernels.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"

namespace softflow::physics {

namespace {

using la::check;
constexpr int kQuadratureDegree = 5;  // as StokesSystem's

}  // namespace

Eigen::Matrix<double, 18, 18> linearised_tension_block(const element::TriangleNodes& x,
                                                       const std::array<Eigen::Vector3d, 6>& normals,
                                                       double gamma, double radius) {
  const TriangleStiffness k = gamma * (surface_stiffness(x) - (2.0 / (radius * radius)) * surface_mass(x));
  Eigen::Matrix<double, 18, 18> block;
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b) block.block<3, 3>(3 * a, 3 * b) = k(a, b) * normals[a] * normals[b].transpose();
  return block;
}

struct OscillatorySystem::Impl {
  std::unique_ptr<la::CsrMatrix> matrix;
  /// One LU solver for every frequency: the pattern does not change, so
  /// MUMPS's analysis (ordering, symbolic factorisation) is done once and
  /// each frequency only factors numerically.
  la::Solver ksp;
  // Per assembled tet: its real and imaginary blocks; per face: the two couplings.
  std::vector<la::CsrMatrix::Block> real_blocks, imaginary_blocks, upper_blocks, lower_blocks;
};

OscillatorySystem::OscillatorySystem(const mesh::Mesh& mesh)
    : mesh_(mesh),
      dofs_(make_stokes_dof_map(mesh, false)),
      tabulation_(kQuadratureDegree),
      impl_(std::make_unique<Impl>()) {
  for (int k = 1; k <= mesh_.n_objects; ++k) surfaces_.push_back(extract_interface(mesh_, k));
  node_normal_ = interface_node_normals(surfaces_, mesh_);
  const auto owned = dofs_.ownership(la::mpi_rank(), la::mpi_size());
  range_ = {index(owned.begin, 0), index(owned.end, 0)};
  // As StokesSystem: every element with a row here is assembled here.
  const auto [first_node, last_node] = fem::rank_node_range(mesh_.n_nodes(), la::mpi_rank(), la::mpi_size());
  assembled_tets_ = fem::elements_touching(mesh_, first_node, last_node);
  for (int f = 0; f < static_cast<int>(mesh_.interface_faces.size()); ++f)
    for (int node : mesh_.interface_faces[f])
      if (range_.owns(index(dofs_.dof(kVelocityField, node, 0, 0), 0))) {
        assembled_faces_.push_back(f);
        break;
      }
  create_matrix();
}

OscillatorySystem::~OscillatorySystem() = default;

void OscillatorySystem::create_matrix() {
  const PetscInt n = n_unknowns();
  impl_->matrix = std::make_unique<la::CsrMatrix>(range_, n, range_, n);
  auto& m = *impl_->matrix;
  auto part_of = [&](std::span<const int> dofs, int part, bool rows) {
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
  for (int f : assembled_faces_) {
    std::array<int, 18> d;
    for (int k = 0; k < 6; ++k)
      for (int c = 0; c < 3; ++c) d[3 * k + c] = dofs_.dof(kVelocityField, mesh_.interface_faces[f][k], 0, c);
    const auto real_rows = part_of(d, 0, true), imaginary_rows = part_of(d, 1, true);
    const auto real_columns = part_of(d, 0, false), imaginary_columns = part_of(d, 1, false);
    impl_->upper_blocks.push_back(
        m.add_block(std::span<const PetscInt>(real_rows), std::span<const PetscInt>(imaginary_columns)));
    impl_->lower_blocks.push_back(
        m.add_block(std::span<const PetscInt>(imaginary_rows), std::span<const PetscInt>(real_columns)));
  }
  m.create();
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
  auto& m = *impl_->matrix;
  TetMatrix ke;
  for (std::size_t e = 0; e < assembled_tets_.size(); ++e) {
    const int t = assembled_tets_[e];
    ke.setZero();
    add_stokes_tet_matrix(fem::tet_nodes(mesh_, t), tabulation_, problem.viscosity.at(mesh_.tet_region[t]), ke);
    m.set_block(impl_->real_blocks[e], ke);
    m.set_block(impl_->imaginary_blocks[e], ke);
  }
  for (std::size_t i = 0; i < assembled_faces_.size(); ++i) {
    const auto& tri = mesh_.interface_faces[assembled_faces_[i]];
    const int object = mesh_.interface_object[assembled_faces_[i]];
    std::array<Eigen::Vector3d, 6> normals;
    for (int a = 0; a < 6; ++a) normals[a] = node_normal_[tri[a]];
    const auto t = linearised_tension_block(fem::triangle_nodes(mesh_, tri), normals,
                                            problem.interfacial_tension[object - 1], problem.radius[object - 1]);
    m.set_block(impl_->upper_blocks[i], t / problem.omega);
    m.set_block(impl_->lower_blocks[i], -t / problem.omega);
  }
  m.assemble();

  // Walls: the real amplitude g, the imaginary 0; the gauge's two pressures 0.
  la::Vector rhs = la::make_vector(range_.size(), n_unknowns());
  la::Vector x = la::make_vector(range_.size(), n_unknowns());
  check(VecSet(rhs.get(), 0.0), "VecSet");
  check(VecSet(x.get(), 0.0), "VecSet");
  std::vector<PetscInt> rows;
  std::vector<PetscScalar> values;
  std::vector<char> seen(range_.size(), 0);
  auto constrain = [&](PetscInt row, double value) {
    if (!range_.owns(row) || seen[row - range_.begin]) return;
    seen[row - range_.begin] = 1;
    rows.push_back(row);
    values.push_back(value);
  };
  for (const auto& face : mesh_.boundary_faces)
    for (int node : face) {
      const Eigen::Vector3d g =
          problem.boundary_velocity ? problem.boundary_velocity(mesh_.nodes[node]) : Eigen::Vector3d::Zero();
      for (int c = 0; c < 3; ++c) {
        constrain(index(dofs_.dof(kVelocityField, node, 0, c), 0), g(c));
        constrain(index(dofs_.dof(kVelocityField, node, 0, c), 1), 0.0);
      }
    }
  for (int part : {0, 1}) constrain(index(dofs_.dof(kPressureField, problem.pressure_gauge_node, 0), part), 0.0);
  check(VecSetValues(x.get(), static_cast<PetscInt>(rows.size()), rows.data(), values.data(), INSERT_VALUES),
        "VecSetValues(x)");
  check(VecAssemblyBegin(x.get()), "VecAssemblyBegin");
  check(VecAssemblyEnd(x.get()), "VecAssemblyEnd");
  check(MatZeroRowsColumns(m.get(), static_cast<PetscInt>(rows.size()), rows.data(), 1.0, x.get(), rhs.get()),
        "MatZeroRowsColumns");
  OscillatoryResponse out;
  out.assembly_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const auto solve_start = std::chrono::steady_clock::now();
  if (!impl_->ksp) {
    // Saddle-point LU pivots off the diagonal: room for it, as StokesSystem's.
    la::set_default_option("-oscillatory_mat_mumps_icntl_14", "80");
    impl_->ksp = la::lu_solver(m.get(), "oscillatory_");
  } else {
    check(KSPSetOperators(impl_->ksp.get(), m.get(), m.get()), "KSPSetOperators");
  }
  KSP ksp = impl_->ksp.get();
  check(KSPSolve(ksp, rhs.get(), x.get()), "KSPSolve(oscillatory)");
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
        "= {}{}); the direct solve is for up to a few hundred thousand unknowns: coarsen the mesh "
        "(mesh.equator_nodes, mesh.far_size) or use fewer drops",
        problem.omega, n_unknowns(), KSPConvergedReasons[reason], info,
        info == -9 || info == -8 || info == -13 ? ": out of memory or workspace" : ""));
  }
  out.solve.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - solve_start).count();
  out.solve.iterations = 1;
  out.solve.reason = KSPConvergedReasons[reason];

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
        const int d = dofs_.dof(kVelocityField, node, 0, c);
        un += Complex(out.real[d], out.imaginary[d]) * node_normal_[node](c);
      }
      out.normal_displacement[node] = un / Complex(0.0, problem.omega);
    }
  return out;
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
  // delta int_S n n ds, on the outward-oriented interface.
  static const element::QuadratureRule rule = element::triangle_rule(5);
  const auto& surface = surfaces_.at(object - 1);
  const double radius = problem.radius.at(object - 1);
  Matrix3c tension_change = Matrix3c::Zero();
  for (const auto& tri : surface.triangles) {
    element::TriangleNodes x;
    std::array<Complex, 6> zeta;
    for (int a = 0; a < 6; ++a) {
      x.col(a) = mesh_.nodes[surface.volume_node[tri[a]]];
      zeta[a] = response.normal_displacement[surface.volume_node[tri[a]]];
    }
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(x, rule.points[q]);
      const auto values = element::p2_triangle_values(rule.points[q]);
      Complex z(0.0, 0.0);
      Eigen::Vector3cd grad_z = Eigen::Vector3cd::Zero();
      for (int a = 0; a < 6; ++a) {
        z += values[a] * zeta[a];
        grad_z += zeta[a] * p.surface_gradients.row(a).transpose().cast<Complex>();
      }
      const Eigen::Vector3cd n = p.normal.cast<Complex>();
      const double w = rule.weights[q] * p.area_scale;
      tension_change += w * (-(grad_z * n.transpose()) - n * grad_z.transpose() + (2.0 / radius) * z * (n * n.transpose()));
    }
  }
  const double gamma = problem.interfacial_tension.at(object - 1);
  const Complex trace_third = tension_change.trace() / 3.0;
  return (lambda - 1.0) * eta_m * volume_term - gamma * (tension_change - trace_third * Matrix3c::Identity());
}

}  // namespace softflow::physics
