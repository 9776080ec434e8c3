// The volume of each region of a curved P2 mesh (index = region, 0 the
// matrix), from the isoparametric map: det J has degree 3, so the degree-3
// rule integrates it exactly.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::test_support {

inline std::vector<double> region_volumes(const mesh::Mesh& m) {
  const auto rule = element::tetrahedron_rule(3);
  std::vector<double> volume(m.n_objects + 1, 0.0);
  for (int t = 0; t < m.n_tets(); ++t) {
    Eigen::Matrix<double, 3, 10> x;
    for (int k = 0; k < 10; ++k) x.col(k) = m.nodes[m.tets[t][k]];
    for (int q = 0; q < rule.size(); ++q)
      volume[m.tet_region[t]] += rule.weights[q] * (x * element::p2_tet_gradients(rule.points[q])).determinant();
  }
  return volume;
}

}  // namespace softflow::test_support
