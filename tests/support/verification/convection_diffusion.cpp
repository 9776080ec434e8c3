#include "support/verification/convection_diffusion.hpp"

#include <cmath>

#include "softflow/element/shape_functions.hpp"
#include "softflow/fem/field.hpp"
#include "softflow/fem/supg.hpp"
#include "support/verification/curved_box.hpp"

namespace softflow::verification {

using Eigen::Vector3d;

namespace {

const Vector3d kVelocity(1.0, 0.6, -0.3);

// Exact solution per region: smooth in each, discontinuous across the interface.
double exact(const Vector3d& x, int region) {
  if (region == 0) return std::sin(x.x()) * std::cos(x.y()) * std::exp(0.5 * x.z());
  return 2.0 + x.x() * x.y() * x.z() + std::cos(2.0 * x.x());
}
Vector3d exact_gradient(const Vector3d& x, int region) {
  if (region == 0) {
    const double e = std::exp(0.5 * x.z());
    return {std::cos(x.x()) * std::cos(x.y()) * e, -std::sin(x.x()) * std::sin(x.y()) * e,
            0.5 * std::sin(x.x()) * std::cos(x.y()) * e};
  }
  return {x.y() * x.z() - 2.0 * std::sin(2.0 * x.x()), x.x() * x.z(), x.x() * x.y()};
}
double exact_laplacian(const Vector3d& x, int region) {
  if (region == 0) return -1.75 * exact(x, 0);
  return -4.0 * std::cos(2.0 * x.x());
}
double source(const Vector3d& x, int region, double eps) {
  return -eps * exact_laplacian(x, region) + kVelocity.dot(exact_gradient(x, region));
}


}  // namespace

ConvectionDiffusionErrors solve_convection_diffusion(int n, double eps, bool supg) {
  const auto mesh = curved_box_with_block(n, 0.1);
  auto space = std::make_shared<fem::Space>(mesh, 1, fem::Continuity::per_region);
  fem::Field phi(mesh, "phi", space, 1);
  const auto& dofs = phi.dofs();
  const auto range = phi.ownership();
  auto a = fem::element_matrix(phi);
  la::Vector rhs = la::make_vector(range.size(), dofs.n_dofs());
  la::check(VecSet(rhs.get(), 0.0), "VecSet");

  const fem::TetTabulation tab(5);
  const Eigen::Matrix<double, 4, 3> ref_grad = element::p1_tet_gradients();
  const double speed = kVelocity.norm();
  std::size_t e = 0;
  for (int t : phi.owned_elements()) {
    const auto points = fem::quadrature_points(mesh, tab, t);
    double volume = 0.0;
    for (const auto& p : points) volume += p.weight;
    const double tau = supg ? fem::supg_tau(fem::element_length(volume), speed, eps) : 0.0;
    Eigen::Matrix4d ke = Eigen::Matrix4d::Zero();
    Eigen::Vector4d fe = Eigen::Vector4d::Zero();
    for (const auto& p : points) {
      const Eigen::Matrix<double, 4, 3> g = ref_grad * p.map.inverse_jacobian;
      const Eigen::Vector4d n(tab.p1[p.q][0], tab.p1[p.q][1], tab.p1[p.q][2], tab.p1[p.q][3]);
      const Eigen::Vector4d b_grad = g * kVelocity;  // b . grad N_j
      const double f = source(p.x, p.region, eps);
      // Row i = test function N_i, column j = trial function N_j.
      ke += p.weight * (eps * g * g.transpose()          // (1)
                        + n * b_grad.transpose()          // (2)
                        + tau * b_grad * b_grad.transpose());  // (3)
      fe += p.weight * f * (n + tau * b_grad);
    }
    a.matrix->set_block(a.blocks[e++], ke);
    const auto d = dofs.element_dofs(t);
    la::check(VecSetValues(rhs.get(), 4, d.data(), fe.data(), ADD_VALUES), "VecSetValues");
  }
  a.matrix->assemble();
  la::check(VecAssemblyBegin(rhs.get()), "VecAssemblyBegin");
  la::check(VecAssemblyEnd(rhs.get()), "VecAssemblyEnd");

  // Dirichlet data on the outer boundary and on both sides of the interface
  // (each copy takes its own region's exact value).
  std::vector<char> fixed_node(mesh.n_nodes(), 0);
  for (const auto& face : mesh.boundary_faces)
    for (int k = 0; k < 3; ++k) fixed_node[face[k]] = 1;
  std::vector<PetscInt> fixed;
  std::vector<PetscScalar> values;
  for (int d = range.begin; d < range.end; ++d) {
    const int node = dofs.node_of(d);
    if (fixed_node[node] || space->copies(node).size() > 1) {
      fixed.push_back(d);
      values.push_back(exact(mesh.nodes[node], dofs.region_of(d)));
    }
  }
  la::Vector x = la::make_vector(range.size(), dofs.n_dofs());
  la::check(VecSet(x.get(), 0.0), "VecSet");
  la::check(VecSetValues(x.get(), static_cast<PetscInt>(fixed.size()), fixed.data(), values.data(),
                         INSERT_VALUES),
            "VecSetValues");
  la::check(VecAssemblyBegin(x.get()), "VecAssemblyBegin");
  la::check(VecAssemblyEnd(x.get()), "VecAssemblyEnd");
  la::check(MatZeroRowsColumns(a.matrix->get(), static_cast<PetscInt>(fixed.size()), fixed.data(), 1.0,
                               x.get(), rhs.get()),
            "MatZeroRowsColumns");

  const la::Solver ksp = la::lu_solver(a.matrix->get(), "convection_diffusion_");
  la::check(KSPSolve(ksp.get(), rhs.get(), phi.vector()), "KSPSolve");
  phi.update_ghosts();

  ConvectionDiffusionErrors err;
  err.n = n;
  err.unknowns = dofs.n_dofs();
  err.peclet = kVelocity.norm() * (2.0 / n) / (2.0 * eps);
  double overshoot = -1e300;
  for (int t : phi.owned_elements()) {
    const Eigen::VectorXd c = phi.element_coefficients(t);
    for (int k = 0; k < 4; ++k)
      overshoot = std::max(overshoot, c(k) - exact(mesh.nodes[mesh.tets[t][k]], mesh.tet_region[t]));
  }
  MPI_Allreduce(&overshoot, &err.overshoot, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  double local[2] = {0.0, 0.0};
  const fem::TetTabulation fine(6);
  for (int t : phi.owned_elements())
    for (const auto& p : fem::quadrature_points(mesh, fine, t)) {
      local[0] += p.weight * std::pow(phi.value(p)(0) - exact(p.x, p.region), 2);
      local[1] += p.weight * (phi.gradient(p).row(0).transpose() -
                              exact_gradient(p.x, p.region)).squaredNorm();
    }
  double total[2];
  MPI_Allreduce(local, total, 2, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
  err.l2 = std::sqrt(total[0]);
  err.h1 = std::sqrt(total[1]);
  return err;
}

}  // namespace softflow::verification
