// Small-amplitude oscillatory shear of drops solved in the frequency domain:
// one complex Stokes solve per frequency around the resting spherical drops.
#pragma once

#include <array>
#include <complex>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "softflow/fem/dof_map.hpp"
#include "softflow/fem/tabulation.hpp"
#include "softflow/la/petsc.hpp"
#include "softflow/la/saddle_point_solver.hpp"
#include "softflow/mesh/mesh.hpp"
#include "softflow/physics/interface/interface_mesh.hpp"
#include "softflow/physics/stokes/stokes_problem.hpp"

namespace softflow::physics {

using Complex = std::complex<double>;
using Matrix3c = Eigen::Matrix3cd;

/// One frequency of the linearised problem. Every field is a complex
/// amplitude a with the physical value Re(a e^{i omega t}); the walls move
/// with the real amplitude g(x) (in phase with the wall shear rate).
struct OscillatoryProblem {
  /// Viscosity of region r (0 = matrix, k = object k).
  std::vector<double> viscosity;
  /// Gamma of object k at index k - 1 (every object a drop).
  std::vector<double> interfacial_tension;
  /// The resting radius of object k at index k - 1 (the drops are spheres at rest).
  std::vector<double> radius;
  /// Navier slip of each object (InterfaceSlip: dimensional, missing
  /// entries 0). Needs a system built with interface_slip.
  InterfaceSlip slip;
  /// Velocity amplitude on every outer boundary face.
  std::function<Eigen::Vector3d(const Eigen::Vector3d&)> boundary_velocity;
  double omega = 0.0;  ///< angular frequency, > 0
  /// The pressure is zero at this matrix vertex (real and imaginary parts).
  int pressure_gauge_node = -1;
};

struct OscillatoryResponse {
  /// Velocity and pressure amplitudes (real and imaginary parts) in the
  /// layout of make_stokes_dof_map(mesh, false), every dof, on every rank.
  std::vector<double> real, imaginary;
  /// zeta, the interface's normal displacement amplitude at each interface
  /// node (indexed by mesh node; 0 elsewhere).
  std::vector<Complex> normal_displacement;
  /// The direct path: one LU solve (iterations 1). The iterative path: the
  /// outer FGMRES iterations; inner_solves and inner_iterations count the
  /// real Stokes solves of its preconditioner.
  la::SolveReport solve;
  int inner_solves = 0, inner_iterations = 0;
  double assembly_seconds = 0.0;
};

/// Drops at rest are spheres: pressure jump 2 Gamma / R, no flow. A small
/// oscillation of the walls moves each interface by zeta n (n the sphere's
/// outward normal) and the flow is Stokes flow in the resting domains with,
/// on each sphere S of radius R (the linearised interface conditions):
///
///   [sigma] n = Gamma (lap_s zeta + 2 zeta / R^2) n     (the curvature's change),
///   i omega zeta = u . n                                 (kinematic condition),
///
/// the first in weak form (by parts on the closed S)
///   Gamma int_S [grad_s zeta . grad_s (v.n) - 2/R^2 zeta v.n] ds
/// on the momentum equation's left side. The tension of the resting sphere
/// and the pressure jump that balances it cancel to first order (their
/// changes with the normal's tilt are equal and opposite), so only the
/// curvature's change remains. zeta is the P2 interpolant of its nodal
/// values, and the kinematic condition holds at the interface nodes with
/// the nodal normals of interface_node_normals: zeta_a = u_a . n_a / (i
/// omega), so zeta is eliminated and the tension becomes a term
/// -(i / omega) T u with
///
///   T = Gamma N^T (S - 2/R^2 M) N,
///
/// S and M the surface Laplacian and mass of the P2 interface, N the nodal
/// normal projection. The complex system (A - i T / omega) u + B^T p = 0,
/// B u = 0 is solved in real form, unknowns interleaved (re, im) per dof:
///
///   [ A      T/omega ] [u_r]   [B^T p_r]
///   [ -T/omega   A   ] [u_i] + [B^T p_i] = 0,
///
/// with MUMPS (one factorisation per frequency) or, for systems too large to
/// factor, by FGMRES preconditioned with PRESB (Axelsson and Kucherov 2000;
/// Axelsson, Neytcheva and Ahmad 2014): with v = -u_i the system is
/// [K, -B; B, K] [u_r; v] = [f_r; -f_i], K the Stokes matrix and B = T/omega,
/// and PRESB's P = [K, -B; B, K + 2B] costs two solves with the real Stokes
/// matrix K + B (the tension's stiffness added, as a semi-implicit step
/// adds its own), each by the iterative saddle-point solver; for symmetric
/// positive K and B the preconditioned eigenvalues lie in [1/2, 1],
/// whatever omega. Limits: omega -> oo is the
/// viscous sphere without tension (Oldroyd's high-frequency limit), omega ->
/// 0 forces u . n -> 0 on S (steady tank-treading: Taylor's viscosity).
/// Newtonian phases. With Navier slip the interface conditions are those of
/// the time domain (n . u continuous, the tangential jump alpha times the
/// matrix's tangential traction), linear already, in both parts; zeta
/// follows the drop's normal velocity.
class OscillatorySystem {
 public:
  /// `method`: direct (MUMPS LU of the real form), iterative (PRESB) or
  /// automatic: direct up to la::kDirectSolverLimit real unknowns.
  /// `interface_slip`: a velocity copy per region coupled by the slip
  /// multipliers (physics/stokes/interface_slip.hpp), in both parts, on
  /// either path (the iterative one preconditions the multipliers as
  /// StokesSystem does, slip_node_preconditioner).
  explicit OscillatorySystem(const mesh::Mesh& mesh,
                             la::SaddlePointMethod method = la::SaddlePointMethod::automatic,
                             bool interface_slip = false);
  ~OscillatorySystem();
  OscillatorySystem(const OscillatorySystem&) = delete;
  OscillatorySystem& operator=(const OscillatorySystem&) = delete;

  /// The Stokes dof map (velocity continuous, pressure per region) each of
  /// the real and imaginary parts uses.
  [[nodiscard]] const fem::DofMap& dofs() const { return dofs_; }
  /// Real unknowns of the solve: twice the Stokes dofs.
  [[nodiscard]] int n_unknowns() const { return 2 * dofs_.n_dofs(); }
  /// The method in use (automatic resolved) and why.
  [[nodiscard]] la::SaddlePointMethod method() const { return method_; }
  [[nodiscard]] const std::string& method_reason() const { return method_reason_; }

  /// Assembles and solves at problem.omega. Collective.
  [[nodiscard]] OscillatoryResponse solve(const OscillatoryProblem& problem);

  /// The stresslet of object k (1-based) in the response (Batchelor 1970;
  /// the time-domain form is simulation::BulkStress's):
  ///   S = (lambda - 1) eta_m int_V 2 D(u) dV - Gamma delta int_S (n n - I/3) ds,
  /// the second term linearised about the sphere: the normal tilts by
  /// -grad_s zeta and the area element grows by 2 zeta / R, so
  ///   delta int_S n n ds = int_S [-(grad_s zeta) n - n grad_s zeta + (2/R) zeta n n] ds.
  /// (The volume term's change with the drop's shape is second order: u is
  /// first order.) Every rank computes it whole from the gathered response.
  [[nodiscard]] Matrix3c stresslet(const OscillatoryProblem& problem, const OscillatoryResponse& response,
                                   int object) const;

  /// Volume of object k's resting mesh region.
  [[nodiscard]] double object_volume(int object) const;

  /// The matrices and solvers (named here for the preconditioner's PETSc callback).
  struct Impl;

 private:
  void create_matrix();
  /// The iterative path's real N-size matrices: K + B, its preconditioning
  /// matrix (pressure block -M/eta) and B alone; the inner solver.
  void create_inner_matrices();
  /// A slip face's dofs as StokesSystem couples them: the velocity rows of
  /// both copies (u_m, u_d) x its multipliers, the multipliers' rows x (u_m,
  /// u_d, lambda).
  struct SlipFaceDofs {
    std::vector<PetscInt> velocity, multipliers, constrained;
  };
  [[nodiscard]] SlipFaceDofs slip_face_dofs(int face) const;
  /// With slip, the iterative path's slip blocks in K + B and its
  /// preconditioning matrix, and the preconditioner's blocks at each
  /// interface node (slip_node_preconditioner).
  void declare_inner_slip_blocks();
  /// Their values: the jump penalty and the multipliers' Schur estimate from
  /// the diagonal of the assembled K + B.
  void assemble_inner_slip_estimate(const OscillatoryProblem& problem);
  /// The iterative path's gauge: the constant pressures as the null spaces
  /// of the real form and of K + B (the direct path pins the gauge instead).
  void attach_pressure_nullspaces();
  /// Assembles every matrix of the method at problem.omega and eliminates
  /// the Dirichlet rows (walls; the gauge's pressures on the direct path); returns the real
  /// system's right-hand side and initial guess.
  std::pair<la::Vector, la::Vector> assemble(const OscillatoryProblem& problem);
  void solve_direct(const OscillatoryProblem& problem, Vec rhs, Vec x, OscillatoryResponse& out);
  void solve_iterative(const OscillatoryProblem& problem, Vec rhs, Vec x, OscillatoryResponse& out);
  /// The side the tension acts on: the drop's copy with slip (so that the
  /// multipliers are the matrix's traction, as in StokesSystem), else the shared one.
  [[nodiscard]] int tension_region(int face) const { return slip_ ? mesh_.interface_object[face] : 0; }
  /// Real index of dof d's real (part 0) or imaginary (part 1) amplitude.
  static PetscInt index(PetscInt dof, int part) { return 2 * dof + part; }
  /// Interface faces (each rank declares every face: its rows of other
  /// ranks are dropped; few faces, and with slip they carry three fields).
  [[nodiscard]] int n_faces() const { return static_cast<int>(mesh_.interface_faces.size()); }

  const mesh::Mesh& mesh_;
  fem::DofMap dofs_;
  fem::TetTabulation tabulation_;
  std::vector<InterfaceMesh> surfaces_;  // outward oriented, one per object
  std::vector<Eigen::Vector3d> node_normal_;
  bool slip_ = false;
  la::SaddlePointMethod method_;
  std::string method_reason_;
  la::OwnershipRange range_;  // of the real unknowns
  std::vector<int> assembled_tets_;
  std::unique_ptr<Impl> impl_;
};

/// The linearised tension's block on one curved P2 interface triangle over
/// the velocities of its 6 nodes (3 a + d): Gamma N^T (S - 2/R^2 M) N with
/// S, M its surface Laplacian and mass and N_{a, 3a+d} = normals[a]_d.
Eigen::Matrix<double, 18, 18> linearised_tension_block(const element::TriangleNodes& x,
                                                       const std::array<Eigen::Vector3d, 6>& normals,
                                                       double gamma, double radius);

/// Gamma N^T S N: the same without the -2/R^2 mass term, positive
/// semidefinite (the iterative path's preconditioning matrix takes it).
Eigen::Matrix<double, 18, 18> normal_surface_stiffness_block(
    const element::TriangleNodes& x, const std::array<Eigen::Vector3d, 6>& normals, double gamma);

}  // namespace softflow::physics
