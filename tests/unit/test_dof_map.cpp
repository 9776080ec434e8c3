// Dof maps: doubled interface unknowns, periodic identification, numbering.
#include <set>

#include <gtest/gtest.h>

#include "softflow/fem/dof_map.hpp"
#include "softflow/mesh/structured_box.hpp"

using namespace softflow;

namespace {

// A 4^3 box whose central 2^3 cubes (48 tets) form object 1.
mesh::Mesh box_with_inner_block(bool periodic) {
  mesh::Box box;
  box.length = box.height = box.width = 4.0;
  box.periodic_x = box.periodic_z = periodic;
  auto mesh = mesh::structured_box(box, 4, 4, 4);
  mesh.n_objects = 1;
  for (int t = 0; t < mesh.n_tets(); ++t) {
    mesh::Point c = mesh::Point::Zero();
    for (int k = 0; k < 4; ++k) c += mesh.nodes[mesh.tets[t][k]] / 4;
    if (c.cwiseAbs().maxCoeff() < 1.0) mesh.tet_region[t] = 1;
  }
  return mesh;
}

bool on_inner_block_surface(const mesh::Point& x) {
  return std::abs(x.cwiseAbs().maxCoeff() - 1.0) < 1e-12;
}

}  // namespace

TEST(StokesDofMap, PressureIsDoubledAtTheInterfaceVelocityIsShared) {
  const auto mesh = box_with_inner_block(false);
  const fem::StokesDofMap dofs(mesh, false);
  int n_interface_vertices = 0;
  for (int i = 0; i < mesh.n_nodes(); ++i) {
    if (!on_inner_block_surface(mesh.nodes[i])) continue;
    EXPECT_EQ(dofs.velocity_dof(i, 0), dofs.velocity_dof(i, 1));
    EXPECT_GE(dofs.velocity_dof(i, 0), 0);
    if (mesh.is_vertex[i]) {
      ++n_interface_vertices;
      EXPECT_NE(dofs.pressure_dof(i, 0), dofs.pressure_dof(i, 1));
      EXPECT_GE(dofs.pressure_dof(i, 1), 0);
    }
  }
  EXPECT_EQ(n_interface_vertices, 26);  // 3^3 - 1 lattice points on the block surface
  // 5^3 vertices + 26 doubled pressures; 9^3 P2 nodes x 3 velocities.
  EXPECT_EQ(dofs.n_pressure_dofs(), 125 + 26);
  EXPECT_EQ(dofs.n_velocity_dofs(), 3 * 729);
}

TEST(StokesDofMap, DoubledVelocityGivesEachSideItsOwnCopy) {
  const auto mesh = box_with_inner_block(false);
  const fem::StokesDofMap dofs(mesh, true);
  int n_interface_nodes = 0;
  for (int i = 0; i < mesh.n_nodes(); ++i)
    if (on_inner_block_surface(mesh.nodes[i])) {
      ++n_interface_nodes;
      EXPECT_NE(dofs.velocity_dof(i, 0), dofs.velocity_dof(i, 1));
    }
  EXPECT_EQ(n_interface_nodes, 5 * 5 * 5 - 27);
  EXPECT_EQ(dofs.n_velocity_dofs(), 3 * (729 + n_interface_nodes));
}

TEST(StokesDofMap, PeriodicNodesShareUnknownsIncludingEdgeNodesAndCorners) {
  const auto mesh = box_with_inner_block(true);
  const fem::StokesDofMap dofs(mesh, false);
  // Periodic in x and z: P2 nodes per direction 9 -> 8 unique in x and z.
  EXPECT_EQ(dofs.n_velocity_dofs(), 3 * 8 * 9 * 8);
  for (int i = 0; i < mesh.n_nodes(); ++i) {
    const auto& x = mesh.nodes[i];
    if (std::abs(x.x() - 2.0) < 1e-12 || std::abs(x.z() - 2.0) < 1e-12) {
      const int m = mesh.master(i);
      EXPECT_NE(m, i);
      EXPECT_NEAR(mesh.nodes[m].y(), x.y(), 1e-12);
      EXPECT_EQ(dofs.velocity_dof(i, 0), dofs.velocity_dof(m, 0));
    }
  }
}

TEST(StokesDofMap, NumberingIsContiguousPerNodeAndCoversEveryDofOnce) {
  const auto mesh = box_with_inner_block(true);
  const fem::StokesDofMap dofs(mesh, false);
  std::set<int> seen;
  for (int t = 0; t < mesh.n_tets(); ++t)
    for (int d : dofs.tet_dofs(t)) {
      ASSERT_GE(d, 0);
      ASSERT_LT(d, dofs.n_dofs());
      seen.insert(d);
    }
  EXPECT_EQ(static_cast<int>(seen.size()), dofs.n_dofs());
  for (int i = 0; i + 1 < dofs.n_dofs(); ++i)
    EXPECT_LE(dofs.node_of(i), dofs.node_of(i + 1));  // node by node
  for (int t = 0; t < mesh.n_tets(); ++t)
    for (int k = 0; k < 10; ++k)
      EXPECT_TRUE(dofs.is_velocity(dofs.tet_dofs(t)[3 * k]));
}
