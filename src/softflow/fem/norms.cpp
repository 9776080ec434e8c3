#include "softflow/fem/norms.hpp"

#include <algorithm>
#include <cmath>

#include "softflow/fem/tabulation.hpp"

namespace softflow::fem {

StokesErrors stokes_errors(const mesh::Mesh& mesh, const DofMap& dofs,
                           const std::vector<double>& solution, const VectorField& velocity,
                           const ScalarField& pressure) {
  static const TetTabulation tab(8);
  StokesErrors e;
  double eu2 = 0.0, ep2 = 0.0, ep1 = 0.0, volume = 0.0;
  const int u_at = dofs.element_offset(dofs.field_index("velocity"));
  const int p_at = dofs.element_offset(dofs.field_index("pressure"));
  for (int t = 0; t < mesh.n_tets(); ++t) {
    const int region = mesh.tet_region[t];
    const auto x = tet_nodes(mesh, t);
    const auto all = dofs.element_dofs(t);
    const int* u = all.data() + u_at;
    const int* p = all.data() + p_at;
    for (int q = 0; q < tab.rule.size(); ++q) {
      const auto map = element::tet_map(x, tab.p2_grad[q]);
      const double w = tab.rule.weights[q] * map.det_jacobian;
      Eigen::Vector3d xq = Eigen::Vector3d::Zero(), uh = Eigen::Vector3d::Zero();
      for (int k = 0; k < 10; ++k) {
        xq += tab.p2[q][k] * x.col(k);
        for (int c = 0; c < 3; ++c) uh(c) += tab.p2[q][k] * solution[u[3 * k + c]];
      }
      double ph = 0.0;
      for (int i = 0; i < 4; ++i) ph += tab.p1[q][i] * solution[p[i]];
      eu2 += w * (uh - velocity(xq, region)).squaredNorm();
      const double dp = ph - pressure(xq, region);
      ep2 += w * dp * dp;
      ep1 += w * dp;
      volume += w;
    }
    for (int k = 0; k < 10; ++k) {
      Eigen::Vector3d uh(solution[u[3 * k]], solution[u[3 * k + 1]], solution[u[3 * k + 2]]);
      const auto& xk = mesh.nodes[mesh.tets[t][k]];
      e.velocity_max_nodal = std::max(e.velocity_max_nodal, (uh - velocity(xk, region)).norm());
      if (k < 4)
        e.pressure_max_nodal =
            std::max(e.pressure_max_nodal, std::abs(solution[p[k]] - pressure(xk, region)));
    }
  }
  e.velocity_l2 = std::sqrt(eu2);
  e.pressure_l2 = std::sqrt(ep2);
  e.pressure_l2_mean_free = std::sqrt(std::max(0.0, ep2 - ep1 * ep1 / volume));
  return e;
}

}  // namespace softflow::fem
