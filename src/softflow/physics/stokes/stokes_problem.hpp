// Data of one two-phase Stokes solve: viscosities, tensions, forcing, boundary values.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

namespace softflow::physics {

using Vec3 = Eigen::Vector3d;

/// Everything that defines one instantaneous Stokes problem on a given mesh:
///
///   -div(2 eta_r D(u)) + grad p = f,  div u = 0   in every region r,
///   (sigma_m - sigma_d) n = Gamma_k n div(n)       on the interface of object k,
///   u = g on the Dirichlet boundary (walls; box faces that are not periodic).
struct StokesProblem {
  /// Viscosity of region r (0 = matrix, k = object k).
  std::vector<double> viscosity;
  /// Interfacial tension Gamma of object k at index k - 1 (0: none).
  std::vector<double> interfacial_tension;
  /// Body force f(x, region); empty means none (the physical problems have none).
  std::function<Vec3(const Vec3&, int)> body_force;
  /// Velocity g(x) on every outer boundary face.
  std::function<Vec3(const Vec3&)> boundary_velocity;
  /// The pressure level is fixed at one matrix vertex (the gauge) to this value.
  int pressure_gauge_node = -1;
  double pressure_gauge_value = 0.0;
};

}  // namespace softflow::physics
