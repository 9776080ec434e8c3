#include "support/verification/curved_box.hpp"

#include <cmath>

#include "support/verification/structured_box.hpp"

namespace softflow::verification {

mesh::Mesh curved_box_with_block(int n, double amplitude) {
  auto mesh = mesh::structured_box({2.0, 2.0, 2.0, false, false}, n, n, n);
  mesh.n_objects = 1;
  for (int t = 0; t < mesh.n_tets(); ++t) {
    mesh::Point c = mesh::Point::Zero();
    for (int k = 0; k < 4; ++k) c += 0.25 * mesh.nodes[mesh.tets[t][k]];
    mesh.tet_region[t] = c.cwiseAbs().maxCoeff() < 0.5 ? 1 : 0;
  }
  mesh::map_nodes(mesh, [amplitude](const mesh::Point& x) {
    const double s = std::sin(M_PI * x.x()) * std::sin(M_PI * x.y()) * std::sin(M_PI * x.z());
    return mesh::Point(x + amplitude * s * mesh::Point(1.0, -0.7, 0.4));
  });
  return mesh;
}

}  // namespace softflow::verification
