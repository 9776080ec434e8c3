#include "softflow/fem/tabulation.hpp"

#include "softflow/element/shape_functions.hpp"

namespace softflow::fem {

TetTabulation::TetTabulation(int degree) : rule(element::tetrahedron_rule(degree)) {
  for (const auto& xi : rule.points) {
    p2.push_back(element::p2_tet_values(xi));
    p2_grad.push_back(element::p2_tet_gradients(xi));
    p1.push_back(element::p1_tet_values(xi));
  }
}

}  // namespace softflow::fem
