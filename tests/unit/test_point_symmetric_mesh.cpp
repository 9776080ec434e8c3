// mesh.point_symmetric: a shear cell meshed so that the rotation by pi about
// z, R (x, y, z) = (-x, -y, z), maps the mesh onto itself (nodes, elements,
// regions, interface and wall faces, periodic classes), the symmetry of
// simple shear around a centred object that the unstructured mesh breaks.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "support/region_volumes.hpp"

#include "softflow/common/error.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/geometry/point_symmetric_mesh.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/mesh/fingerprint.hpp"
#include "softflow/mesh/half_turn.hpp"
#include "softflow/mesh/node_relocation.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/physics/ale/mesh_motion.hpp"

using namespace softflow;
using Eigen::Vector3d;

using softflow::test_support::region_volumes;

namespace {

geometry::ShearCellSpec centred_sphere(bool symmetric) {
  geometry::ShearCellSpec s;
  s.box = {6.0, 4.0, 5.0, true, true};
  geometry::ObjectSpec o;
  o.centre = Vector3d(0.0, 0.0, 0.0);
  s.objects = {o};
  s.sizing.equator_nodes = 12;
  s.sizing.far_size = 1.2;
  s.sizing.point_symmetric = symmetric;
  return s;
}

// image[i] = the node at R x_i (exactly), -1 if there is none.
std::vector<int> partial_half_turn_images(const mesh::Mesh& m) {
  std::map<std::array<double, 3>, int> at;
  for (int i = 0; i < m.n_nodes(); ++i) at[{m.nodes[i].x(), m.nodes[i].y(), m.nodes[i].z()}] = i;
  std::vector<int> image(m.n_nodes(), -1);
  for (int i = 0; i < m.n_nodes(); ++i) {
    const auto p = mesh::half_turn(m.nodes[i]);
    const auto it = at.find({p.x(), p.y(), p.z()});
    if (it != at.end()) image[i] = it->second;
  }
  return image;
}

// Elements as sorted node lists with their region (or tag), to compare sets.
template <class Element, class Label>
std::multiset<std::pair<std::vector<int>, int>> element_set(const std::vector<Element>& elements,
                                                           const std::vector<Label>& labels,
                                                           const std::vector<int>* image) {
  std::multiset<std::pair<std::vector<int>, int>> set;
  for (std::size_t e = 0; e < elements.size(); ++e) {
    std::vector<int> nodes(elements[e].begin(), elements[e].end());
    if (image)
      for (int& n : nodes) n = (*image)[n];
    std::sort(nodes.begin(), nodes.end());
    set.emplace(nodes, static_cast<int>(labels[e]));
  }
  return set;
}

}  // namespace

TEST(PointSymmetricMesh, TheHalfTurnMapsEveryNodeElementAndFaceOntoTheMesh) {
  geometry::MeshReport report;
  const auto m = geometry::build_shear_cell(centred_sphere(true), &report);
  EXPECT_GT(report.min_quality, 0.05);
  const auto image = partial_half_turn_images(m);
  ASSERT_EQ(std::count(image.begin(), image.end(), -1), 0);  // to the bit

  // The same tetrahedra in the same regions, the same interface faces with
  // the same orientation (R is proper: a face's node order turns with it).
  EXPECT_EQ(element_set(m.tets, m.tet_region, &image), element_set(m.tets, m.tet_region, nullptr));
  for (std::size_t f = 0; f < m.interface_faces.size(); ++f) {
    const auto& t = m.interface_faces[f];
    const Vector3d n = (m.nodes[t[1]] - m.nodes[t[0]]).cross(m.nodes[t[2]] - m.nodes[t[0]]);
    EXPECT_GT(n.dot(m.nodes[t[0]]), 0.0) << "face " << f << " points into the sphere";
  }
  EXPECT_EQ(element_set(m.interface_faces, m.interface_object, &image),
            element_set(m.interface_faces, m.interface_object, nullptr));
  // Walls: the bottom one is the top one's image, on y = -H/2.
  std::vector<int> swapped(m.boundary_face_tag.size());
  for (std::size_t f = 0; f < swapped.size(); ++f) {
    const int tag = static_cast<int>(m.boundary_face_tag[f]);
    swapped[f] = tag == 0 ? 1 : tag == 1 ? 0 : tag;
    for (int node : m.boundary_faces[f]) EXPECT_NEAR(std::abs(m.nodes[node].y()), 2.0, 1e-12);
  }
  EXPECT_EQ(element_set(m.boundary_faces, swapped, &image), element_set(m.boundary_faces, m.boundary_face_tag, nullptr));
  EXPECT_EQ(std::count(m.boundary_face_tag.begin(), m.boundary_face_tag.end(), mesh::BoundaryTag::wall_bottom),
            std::count(m.boundary_face_tag.begin(), m.boundary_face_tag.end(), mesh::BoundaryTag::wall_top));

  // The cell is filled once: the regions' volumes add up to the box's, and
  // the sphere's is the P2 sphere's.
  const auto volume = region_volumes(m);
  EXPECT_NEAR(volume[0] + volume[1], 6.0 * 4.0 * 5.0, 1e-9);
  EXPECT_NEAR(volume[1], 4.0 / 3.0 * M_PI, 0.01 * 4.0 / 3.0 * M_PI);

  // Periodic classes: images of classes are classes, members differ by
  // lattice vectors, and the x and z faces are identified.
  ASSERT_EQ(static_cast<int>(m.periodic_master.size()), m.n_nodes());
  int on_x_max = 0;
  for (int i = 0; i < m.n_nodes(); ++i) {
    const int j = m.periodic_master[i];
    const Vector3d d = m.nodes[i] - m.nodes[j];
    EXPECT_NEAR(d.x(), 6.0 * std::round(d.x() / 6.0), 1e-12);
    EXPECT_EQ(d.y(), 0.0);
    EXPECT_NEAR(d.z(), 5.0 * std::round(d.z() / 5.0), 1e-12);
    EXPECT_EQ(m.periodic_master[image[i]], m.periodic_master[image[j]]);
    if (std::abs(m.nodes[i].x() - 3.0) < 1e-12) {
      ++on_x_max;
      EXPECT_NE(j, i) << "node " << i << " on x = L/2 has no periodic image";
    }
  }
  EXPECT_GT(on_x_max, 20);
}

TEST(PointSymmetricMesh, TheDefaultMeshIsNotSymmetricAndStaysTheSame) {
  // The symmetry is the key's doing: gmsh's mesh of the whole cell has
  // most nodes without an image (why a centred object drifts on it).
  const auto plain = geometry::build_shear_cell(centred_sphere(false));
  EXPECT_GT(geometry::nodes_without_half_turn_image(plain, 1e-6), plain.n_nodes() / 2);
  const auto symmetric = geometry::build_shear_cell(centred_sphere(true));
  EXPECT_EQ(geometry::nodes_without_half_turn_image(symmetric, 1e-12), 0);
  EXPECT_NE(mesh::fingerprint(plain), mesh::fingerprint(symmetric));
  // Meshing again gives the same symmetric mesh to the bit.
  EXPECT_EQ(mesh::fingerprint(geometry::build_shear_cell(centred_sphere(true))), mesh::fingerprint(symmetric));
}

TEST(PointSymmetricMesh, AnEllipsoidTurnedAboutZIsMeshedSymmetrically) {
  auto spec = centred_sphere(true);
  spec.objects[0].shape = geometry::ObjectShape::ellipsoid;
  spec.objects[0].semi_axes = Vector3d(1.2, 0.8, 0.9);
  spec.objects[0].rotation_deg = Vector3d(0.0, 0.0, 30.0);
  const auto m = geometry::build_shear_cell(spec);
  EXPECT_EQ(geometry::nodes_without_half_turn_image(m, 1e-12), 0);
  EXPECT_NEAR(region_volumes(m)[1], 4.0 / 3.0 * M_PI * 1.2 * 0.8 * 0.9, 0.01 * 4.0 / 3.0 * M_PI);
}

TEST(PointSymmetricMesh, ObjectsTheHalfTurnDoesNotMapOntoThemselvesAreRefused) {
  auto spec = centred_sphere(true);
  spec.objects[0].centre = Vector3d(0.0, 0.3, 0.0);
  try {
    geometry::validate(spec);
    FAIL() << "an off-axis object was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh.point_symmetric"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("objects[1].centre"), std::string::npos) << e.what();
  }
  spec.objects[0].centre = Vector3d(0.0, 0.0, 0.3);  // on the z axis: fine
  EXPECT_NO_THROW(geometry::validate(spec));
  spec.objects[0].shape = geometry::ObjectShape::ellipsoid;
  spec.objects[0].semi_axes = Vector3d(1.2, 0.8, 0.9);
  spec.objects[0].rotation_deg = Vector3d(20.0, 0.0, 0.0);
  EXPECT_THROW(geometry::validate(spec), InputError);
}

TEST(PointSymmetricMesh, NodeRelocationKeepsTheSymmetry) {
  // Every element below 0.6 is repaired: the search moves
  // many free nodes, each mirror pair to mirror positions, to the bit.
  // Searched independently, the pairs end up apart (the compass search
  // tries its directions in an order the half turn does not keep).
  const auto m = geometry::build_shear_cell(centred_sphere(true));
  const auto image = partial_half_turn_images(m);
  const mesh::NodeRelocation relocation(m);
  auto nodes = m.nodes;
  const auto report = relocation.improve(nodes, 0.6, 1);
  EXPECT_GT(report.nodes_moved, 500);  // 926 on this mesh;
  int moved = 0;
  for (int i = 0; i < m.n_nodes(); ++i) {
    moved += nodes[i] != m.nodes[i];
    EXPECT_EQ(nodes[image[i]], mesh::half_turn(nodes[i])) << "node " << i;
    if (image[i] == i) {
      EXPECT_FALSE(relocation.is_free(i)) << "node " << i << " on the z axis";
    }
  }
  EXPECT_GE(moved, report.nodes_moved);  // and the edge nodes a moved vertex takes along
}

// mesh.point_symmetric_start: the symmetric mesh of the object on the z axis,
// carried to y = +-0.3 by the mesh motion's extension: the object moves
// rigidly, the walls stay, and the two carried meshes are each other's
// images under R to the bit (the runs' Stokes solves then keep them mirrored
// to round-off; node relocation would not, and is off by default with the key).
TEST(PointSymmetricStart, TheMirrorStartsAreEachOthersImagesToTheBit) {
  auto spec = centred_sphere(false);
  spec.sizing.point_symmetric_start = true;
  spec.objects[0].centre = Vector3d(0.0, 0.3, 0.0);
  auto centred = geometry::build_shear_cell(spec);  // the mesh before the carry
  // As simulation::build_mesh does: the worst elements relocated first, on
  // the symmetric mesh, which must stay symmetric to the bit for the carry.
  const auto relocated = mesh::NodeRelocation(centred).improve(centred.nodes, 0.3);
  EXPECT_GT(relocated.nodes_moved, 0);
  const auto image = mesh::half_turn_images(centred);
  ASSERT_EQ(image.size(), static_cast<std::size_t>(centred.n_nodes()));

  const Vector3d offset(0.0, 0.3, 0.0);
  auto up = centred, down = centred;
  physics::carry_objects(up, offset);
  physics::carry_objects(down, -offset);
  const auto volumes = region_volumes(centred), carried = region_volumes(up);
  EXPECT_NEAR(carried[1], volumes[1], 1e-12 * volumes[1]);  // the object moved rigidly
  int object_nodes = 0;
  for (int t = 0; t < centred.n_tets(); ++t)
    if (centred.tet_region[t] == 1)
      for (int node : centred.tets[t]) {
        EXPECT_LT((up.nodes[node] - centred.nodes[node] - offset).norm(), 1e-13) << "node " << node;
        ++object_nodes;
      }
  EXPECT_GT(object_nodes, 0);
  for (const auto& face : centred.boundary_faces)
    if (std::abs(std::abs(centred.nodes[face[0]].y()) - 2.0) < 1e-12)  // a wall face
      for (int node : face) EXPECT_EQ(up.nodes[node], centred.nodes[node]);
  for (int i = 0; i < centred.n_nodes(); ++i)
    ASSERT_EQ(down.nodes[image[i]], mesh::half_turn(up.nodes[i])) << "node " << i;
  EXPECT_GT(mesh::min_quality(up), 0.0);

}

// An offset too large for one extension (an element between the object and
// the wall inverts) is carried in steps, each on the mesh the last left;
// the mirror starts stay each other's images to the bit, the object rigid.
TEST(PointSymmetricStart, AnOffsetTooLargeForOneExtensionIsCarriedInSteps) {
  auto spec = centred_sphere(false);
  spec.sizing.point_symmetric = true;
  auto centred = geometry::build_shear_cell(spec);
  const auto image = mesh::half_turn_images(centred);
  ASSERT_EQ(image.size(), static_cast<std::size_t>(centred.n_nodes()));
  // The smallest offset towards the wall (gap 1 at rest) that one extension
  // cannot take and the steps can.
  int steps = 0;
  Vector3d offset;
  for (double y = 0.40; y < 0.95 && steps <= 1; y += 0.05) {
    auto trial = centred;
    offset = Vector3d(0.0, y, 0.0);
    try {
      steps = physics::carry_objects(trial, offset);
    } catch (const MeshError&) {
      steps = -1;  // too large even in steps before one step failed: no such offset here
      break;
    }
  }
  ASSERT_GT(steps, 1) << "no offset up to 0.9 needed more than one step on this mesh";
  auto up = centred, down = centred;
  EXPECT_EQ(physics::carry_objects(up, offset), steps);
  EXPECT_EQ(physics::carry_objects(down, -offset), steps);
  EXPECT_GT(mesh::min_quality(up), 0.0);
  for (int t = 0; t < centred.n_tets(); ++t)
    if (centred.tet_region[t] == 1)
      for (int node : centred.tets[t])
        EXPECT_LT((up.nodes[node] - centred.nodes[node] - offset).norm(), 1e-12) << "node " << node;
  for (int i = 0; i < centred.n_nodes(); ++i)
    ASSERT_EQ(down.nodes[image[i]], mesh::half_turn(up.nodes[i])) << "node " << i;
}

TEST(PointSymmetricStart, OneObjectTurnedAboutZOnly) {
  auto spec = centred_sphere(false);
  spec.sizing.point_symmetric_start = true;
  spec.objects[0].centre = Vector3d(0.2, 0.3, 0.0);
  EXPECT_NO_THROW(geometry::validate(spec));
  auto two = spec;
  two.objects.push_back(spec.objects[0]);
  two.objects[1].centre = Vector3d(0.0, -0.3, 2.6);
  two.box.width = 9.0;
  try {
    geometry::validate(two);
    FAIL() << "two objects were accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh.point_symmetric_start"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("2 objects"), std::string::npos) << e.what();
  }
  spec.objects[0].shape = geometry::ObjectShape::ellipsoid;
  spec.objects[0].semi_axes = Vector3d(1.2, 0.8, 0.9);
  spec.objects[0].rotation_deg = Vector3d(20.0, 0.0, 0.0);
  EXPECT_THROW(geometry::validate(spec), InputError);
  spec.objects[0].rotation_deg = Vector3d(0.0, 0.0, 20.0);
  EXPECT_NO_THROW(geometry::validate(spec));
}
