// Spatial node renumbering: same mesh, compact node ranges, periodic classes kept.
#include <gtest/gtest.h>

#include "softflow/fem/dof_map.hpp"
#include "softflow/mesh/renumber.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "support/verification/structured_box.hpp"

using namespace softflow;

TEST(RenumberNodes, KeepsTheMeshAndMakesNodeRangesCompact) {
  mesh::Box box;
  box.length = box.height = box.width = 2.0;
  auto mesh = mesh::structured_box(box, 6, 6, 6);  // periodic in x and z
  const auto before = mesh;
  mesh::renumber_nodes_spatially(mesh);
  ASSERT_EQ(mesh.n_nodes(), before.n_nodes());
  // Every element has the same node positions, in the same local order.
  for (int t = 0; t < mesh.n_tets(); ++t)
    for (int k = 0; k < 10; ++k)
      EXPECT_EQ(mesh.nodes[mesh.tets[t][k]], before.nodes[before.tets[t][k]]);
  for (std::size_t f = 0; f < mesh.boundary_faces.size(); ++f)
    for (int k = 0; k < 6; ++k)
      EXPECT_EQ(mesh.nodes[mesh.boundary_faces[f][k]], before.nodes[before.boundary_faces[f][k]]);
  // Periodic classes: representatives are closed and the smallest member.
  for (int i = 0; i < mesh.n_nodes(); ++i) {
    const int m = mesh.master(i);
    EXPECT_EQ(mesh.master(m), m);
    EXPECT_LE(m, i);
    const auto d = mesh.nodes[i] - mesh.nodes[m];
    EXPECT_NEAR(d.y(), 0.0, 1e-12);
  }
  EXPECT_EQ(physics::make_stokes_dof_map(mesh, false).n_dofs(),
            physics::make_stokes_dof_map(before, false).n_dofs());
  // The first half of the nodes occupies a clearly smaller box than before
  // (vertices and edge nodes interleaved in space, not vertices first).
  auto extent_of_first_half = [](const mesh::Mesh& m) {
    mesh::Point lo = m.nodes[0], hi = m.nodes[0];
    for (int i = 0; i < m.n_nodes() / 2; ++i) {
      lo = lo.cwiseMin(m.nodes[i]);
      hi = hi.cwiseMax(m.nodes[i]);
    }
    return (hi - lo).prod();
  };
  EXPECT_LT(extent_of_first_half(mesh), 0.75 * extent_of_first_half(before));
}
