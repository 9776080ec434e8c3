// L2 errors of a Taylor-Hood solution against exact fields, region by region.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "softflow/fem/dof_map.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::fem {

struct StokesErrors {
  double velocity_l2 = 0.0;  ///< ||u_h - u||_{L2(Omega)}
  double pressure_l2 = 0.0;  ///< ||p_h - p||_{L2(Omega)}, pressure compared per region
  /// min_c ||p_h - p - c||_{L2(Omega)}: the pressure error free of the gauge.
  /// With velocity prescribed on the whole boundary, p is fixed only up to a
  /// constant, and pinning it at one vertex shifts p_h by that vertex's own error.
  double pressure_l2_mean_free = 0.0;
  double velocity_max_nodal = 0.0;  ///< max over nodes of |u_h - u|
  double pressure_max_nodal = 0.0;  ///< max over vertices (each region's copy) of |p_h - p|
};

using VectorField = std::function<Eigen::Vector3d(const Eigen::Vector3d&, int region)>;
using ScalarField = std::function<double(const Eigen::Vector3d&, int region)>;

/// Errors with a degree-8 quadrature on the (curved) mesh, of the fields
/// "velocity" (3 x P2) and "pressure" (P1) of `dofs`.
StokesErrors stokes_errors(const mesh::Mesh& mesh, const DofMap& dofs,
                           const std::vector<double>& solution, const VectorField& velocity,
                           const ScalarField& pressure);

}  // namespace softflow::fem
