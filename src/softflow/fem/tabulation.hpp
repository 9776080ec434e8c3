// Shape functions tabulated once at the quadrature points of a rule.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "softflow/element/isoparametric.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::fem {

/// P2 and P1 tetrahedron functions at every point of a quadrature rule.
/// Computed once per rule, because the element loops evaluate the same
/// reference values for every element.
struct TetTabulation {
  element::QuadratureRule rule;
  std::vector<std::array<double, 10>> p2;           ///< N_k(xi_q)
  std::vector<Eigen::Matrix<double, 10, 3>> p2_grad;  ///< grad_xi N_k(xi_q)
  std::vector<std::array<double, 4>> p1;            ///< psi_i(xi_q)

  explicit TetTabulation(int degree);
};

/// The 10 node coordinates of tetrahedron `tet`, one per column.
inline element::TetNodes tet_nodes(const mesh::Mesh& mesh, int tet) {
  element::TetNodes x;
  for (int k = 0; k < 10; ++k) x.col(k) = mesh.nodes[mesh.tets[tet][k]];
  return x;
}

/// The 6 node coordinates of a triangle, one per column.
inline element::TriangleNodes triangle_nodes(const mesh::Mesh& mesh, const mesh::Triangle6& tri) {
  element::TriangleNodes x;
  for (int k = 0; k < 6; ++k) x.col(k) = mesh.nodes[tri[k]];
  return x;
}

}  // namespace softflow::fem
