// Spaces and composed dof maps: doubled interface unknowns, periodic
// identification, numbering, element layout.
#include <set>

#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/fem/dof_map.hpp"
#include "softflow/fem/space.hpp"
#include "support/verification/structured_box.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"

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

constexpr int kU = physics::kVelocityField;
constexpr int kP = physics::kPressureField;

}  // namespace

TEST(DofMap, PressureIsDoubledAtTheInterfaceVelocityIsShared) {
  const auto mesh = box_with_inner_block(false);
  const auto dofs = physics::make_stokes_dof_map(mesh, false);
  int n_interface_vertices = 0;
  for (int i = 0; i < mesh.n_nodes(); ++i) {
    if (!on_inner_block_surface(mesh.nodes[i])) continue;
    EXPECT_EQ(dofs.dof(kU, i, 0), dofs.dof(kU, i, 1));
    EXPECT_GE(dofs.dof(kU, i, 0), 0);
    if (mesh.is_vertex[i]) {
      ++n_interface_vertices;
      EXPECT_NE(dofs.dof(kP, i, 0), dofs.dof(kP, i, 1));
      EXPECT_GE(dofs.dof(kP, i, 1), 0);
    }
  }
  EXPECT_EQ(n_interface_vertices, 26);  // 3^3 - 1 lattice points on the block surface
  // 5^3 vertices + 26 doubled pressures; 9^3 P2 nodes x 3 velocities.
  EXPECT_EQ(dofs.n_field_dofs(kP), 125 + 26);
  EXPECT_EQ(dofs.n_field_dofs(kU), 3 * 729);
}

TEST(DofMap, DoubledVelocityGivesEachSideItsOwnCopy) {
  const auto mesh = box_with_inner_block(false);
  const auto dofs = physics::make_stokes_dof_map(mesh, true);
  int n_interface_nodes = 0;
  for (int i = 0; i < mesh.n_nodes(); ++i)
    if (on_inner_block_surface(mesh.nodes[i])) {
      ++n_interface_nodes;
      EXPECT_NE(dofs.dof(kU, i, 0), dofs.dof(kU, i, 1));
    }
  EXPECT_EQ(n_interface_nodes, 5 * 5 * 5 - 27);
  EXPECT_EQ(dofs.n_field_dofs(kU), 3 * (729 + n_interface_nodes));
}

TEST(DofMap, PeriodicNodesShareUnknownsIncludingEdgeNodesAndCorners) {
  const auto mesh = box_with_inner_block(true);
  const auto dofs = physics::make_stokes_dof_map(mesh, false);
  // Periodic in x and z: P2 nodes per direction 9 -> 8 unique in x and z.
  EXPECT_EQ(dofs.n_field_dofs(kU), 3 * 8 * 9 * 8);
  for (int i = 0; i < mesh.n_nodes(); ++i) {
    const auto& x = mesh.nodes[i];
    if (std::abs(x.x() - 2.0) < 1e-12 || std::abs(x.z() - 2.0) < 1e-12) {
      const int m = mesh.master(i);
      EXPECT_NE(m, i);
      EXPECT_NEAR(mesh.nodes[m].y(), x.y(), 1e-12);
      EXPECT_EQ(dofs.dof(kU, i, 0), dofs.dof(kU, m, 0));
    }
  }
}

TEST(DofMap, NumberingIsContiguousPerNodeAndCoversEveryDofOnce) {
  const auto mesh = box_with_inner_block(true);
  const auto dofs = physics::make_stokes_dof_map(mesh, false);
  std::set<int> seen;
  for (int t = 0; t < mesh.n_tets(); ++t)
    for (int d : dofs.element_dofs(t)) {
      ASSERT_GE(d, 0);
      ASSERT_LT(d, dofs.n_dofs());
      seen.insert(d);
    }
  EXPECT_EQ(static_cast<int>(seen.size()), dofs.n_dofs());
  for (int i = 0; i + 1 < dofs.n_dofs(); ++i)
    EXPECT_LE(dofs.node_of(i), dofs.node_of(i + 1));  // node by node
  for (int t = 0; t < mesh.n_tets(); ++t)
    for (int k = 0; k < 10; ++k)
      EXPECT_EQ(dofs.field_of(dofs.element_dofs(t)[3 * k]), kU);
}

TEST(DofMap, ElementLayoutFollowsTheSpacesAndComponentsAreContiguous) {
  const auto mesh = box_with_inner_block(false);
  const auto dofs = physics::make_stokes_dof_map(mesh, false);
  EXPECT_EQ(dofs.element_size(), 30 + 4);
  EXPECT_EQ(dofs.element_offset(kP), 30);
  EXPECT_EQ(dofs.field_index("pressure"), kP);
  EXPECT_THROW((void)dofs.field_index("conformation"), InputError);
  for (int t = 0; t < mesh.n_tets(); t += 7) {
    const auto d = dofs.element_dofs(t);
    for (int k = 0; k < 10; ++k)
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(d[3 * k + c], d[3 * k] + c);
        EXPECT_EQ(dofs.component_of(d[3 * k + c]), c);
        EXPECT_EQ(dofs.node_of(d[3 * k + c]), mesh.master(mesh.tets[t][k]));
      }
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(dofs.region_of(d[30 + i]), mesh.tet_region[t]);
      EXPECT_EQ(d[30 + i], dofs.dof(kP, mesh.tets[t][i], mesh.tet_region[t]));
    }
  }
}

TEST(DofMap, OwnershipRangesTileTheDofsAtNodeBoundaries) {
  const auto mesh = box_with_inner_block(true);
  const auto dofs = physics::make_stokes_dof_map(mesh, false);
  for (int n_ranks : {1, 2, 3, 5}) {
    int expected_begin = 0;
    for (int r = 0; r < n_ranks; ++r) {
      const auto range = dofs.ownership(r, n_ranks);
      EXPECT_EQ(range.begin, expected_begin);
      EXPECT_GE(range.end, range.begin);
      // A node's unknowns never straddle two ranks.
      if (range.begin > 0 && range.begin < dofs.n_dofs()) {
        EXPECT_NE(dofs.node_of(range.begin), dofs.node_of(range.begin - 1));
      }
      expected_begin = range.end;
    }
    EXPECT_EQ(expected_begin, dofs.n_dofs());
  }
}

TEST(Space, P1PerRegionDoublesInterfaceVerticesAndSkipsEdgeNodes) {
  const auto mesh = box_with_inner_block(false);
  const fem::Space p1(mesh, 1, fem::Continuity::per_region);
  EXPECT_EQ(p1.n_element_nodes(), 4);
  EXPECT_EQ(p1.n_dofs(), 125 + 26);
  EXPECT_EQ(p1.describe(), "P1 per region");
  for (int i = 0; i < mesh.n_nodes(); ++i) {
    const auto copies = p1.copies(i);
    if (!mesh.is_vertex[i]) {
      EXPECT_TRUE(copies.empty());
      EXPECT_EQ(p1.dof(i, 0), -1);
    } else if (on_inner_block_surface(mesh.nodes[i])) {
      ASSERT_EQ(copies.size(), 2u);
      EXPECT_EQ(copies[0].region, 0);
      EXPECT_EQ(copies[1].region, 1);
      EXPECT_EQ(p1.region_of(copies[1].dof), 1);
    }
  }
}

TEST(Space, ContinuousP2HasOneDofPerNodeAndAnyComposition) {
  const auto mesh = box_with_inner_block(false);
  auto p2 = std::make_shared<fem::Space>(mesh, 2, fem::Continuity::continuous);
  auto p1 = std::make_shared<fem::Space>(mesh, 1, fem::Continuity::per_region);
  EXPECT_EQ(p2->n_dofs(), 729);
  EXPECT_THROW(fem::Space(mesh, 3, fem::Continuity::continuous), InputError);
  // A 6-component P1 tensor field next to a scalar P2 field: sizes and offsets
  // come from the spaces.
  const fem::DofMap dofs(mesh, {{"phi", p2, 1}, {"conformation", p1, 6}});
  EXPECT_EQ(dofs.n_dofs(), 729 + 6 * (125 + 26));
  EXPECT_EQ(dofs.element_size(), 10 + 24);
  EXPECT_EQ(dofs.element_offset(1), 10);
  EXPECT_EQ(static_cast<int>(dofs.field_dofs(1).size()), dofs.n_field_dofs(1));
}
