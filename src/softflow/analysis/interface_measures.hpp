// Per-object measures of a Stokes solution: volume, area, centre, pressure jump.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "softflow/fem/dof_map.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::analysis {

struct ObjectMeasures {
  int object = 0;                ///< 1-based
  double volume = 0.0;           ///< integral of 1 over the object's (curved) tetrahedra
  double area = 0.0;             ///< integral of 1 over its curved interface
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< centre of volume
  /// Area-averaged pressure jump p_object - p_matrix across the interface
  /// (2 Gamma / R for a sphere at rest, Laplace).
  double pressure_jump = 0.0;
  /// Area-averaged velocity of the interface (the shared no-slip velocity).
  Eigen::Vector3d mean_interface_velocity = Eigen::Vector3d::Zero();
};

std::vector<ObjectMeasures> object_measures(const mesh::Mesh& mesh, const fem::DofMap& dofs,
                                            const std::vector<double>& solution);

/// Largest nodal velocity magnitude over the whole mesh.
double max_velocity(const fem::DofMap& dofs, const std::vector<double>& solution);

}  // namespace softflow::analysis
