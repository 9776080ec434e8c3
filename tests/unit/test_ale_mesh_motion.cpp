// ALE mesh motion: div(k_e grad d) = 0 with interface Dirichlet data, zero on walls.
//
// Every test is MPI-agnostic: run under `mpirun -n 2 unit_tests
// --gtest_filter='AleMeshMotion*'` it checks the distributed solve against
// the same serial references (the mesh is built on every rank).
#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/fem/tabulation.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/mesh/quality.hpp"
#include "support/verification/structured_box.hpp"
#include "softflow/physics/ale/mesh_motion.hpp"

using namespace softflow;
using Eigen::Vector3d;
using physics::AleMeshMotion;

namespace {

// A periodic (x, z) structured box [-3, 3]^3 in 6^3 cubes, walls at y = +-3,
// with the 2x2x2 central cubes [-1, 1]^3 made object 1 and their outer
// faces its interface (oriented out of the object).
mesh::Mesh box_with_block() {
  mesh::Mesh m = mesh::structured_box({6.0, 6.0, 6.0, true, true}, 6, 6, 6);
  m.n_objects = 1;
  auto inside = [](const Vector3d& x) { return x.cwiseAbs().maxCoeff() < 1.0 - 1e-9; };
  for (int t = 0; t < m.n_tets(); ++t) {
    Vector3d c = Vector3d::Zero();
    for (int k = 0; k < 4; ++k) c += 0.25 * m.nodes[m.tets[t][k]];
    m.tet_region[t] = inside(c) ? 1 : 0;
  }
  constexpr int kFaces[4][3] = {{0, 1, 2}, {0, 1, 3}, {1, 2, 3}, {0, 2, 3}};
  std::map<std::array<int, 3>, std::vector<std::pair<int, int>>> faces;  // -> (tet, local face)
  for (int t = 0; t < m.n_tets(); ++t)
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> key{m.tets[t][kFaces[f][0]], m.tets[t][kFaces[f][1]],
                             m.tets[t][kFaces[f][2]]};
      std::sort(key.begin(), key.end());
      faces[key].emplace_back(t, f);
    }
  for (const auto& [key, owners] : faces) {
    if (owners.size() != 2) continue;
    const auto [t0, f0] = owners[0];
    const auto [t1, f1] = owners[1];
    if (m.tet_region[t0] == m.tet_region[t1]) continue;
    const auto [t, f] = m.tet_region[t0] == 1 ? owners[0] : owners[1];
    const auto& tet = m.tets[t];
    std::array<int, 3> v{tet[kFaces[f][0]], tet[kFaces[f][1]], tet[kFaces[f][2]]};
    const int opposite = tet[6 - kFaces[f][0] - kFaces[f][1] - kFaces[f][2]];
    const Vector3d n = (m.nodes[v[1]] - m.nodes[v[0]]).cross(m.nodes[v[2]] - m.nodes[v[0]]);
    if (n.dot(m.nodes[opposite] - m.nodes[v[0]]) > 0) std::swap(v[1], v[2]);
    mesh::Triangle6 tri{v[0], v[1], v[2], -1, -1, -1};
    for (int e = 0; e < 3; ++e) {
      const int a = tri[mesh::kTriangleEdges[e][0]], b = tri[mesh::kTriangleEdges[e][1]];
      for (int te = 0; te < 6; ++te) {
        const int p = tet[mesh::kTetEdges[te][0]], q = tet[mesh::kTetEdges[te][1]];
        if ((p == a && q == b) || (p == b && q == a)) tri[3 + e] = tet[4 + te];
      }
    }
    m.interface_faces.push_back(tri);
    m.interface_object.push_back(1);
  }
  return m;
}

// A small gmsh cell with a unit sphere: 8^3 box, 16 equator nodes, far size 2.
const mesh::Mesh& sphere_cell() {
  static const mesh::Mesh m = [] {
    geometry::ShearCellSpec spec;
    spec.box = {8.0, 8.0, 8.0, true, true};
    geometry::ObjectSpec sphere;
    sphere.centre = Vector3d::Zero();
    sphere.semi_axes = Vector3d::Ones();
    spec.objects = {sphere};
    spec.sizing.equator_nodes = 16;
    spec.sizing.far_size = 2.0;
    spec.sizing.growth = 0.4;
    return geometry::build_shear_cell(spec);
  }();
  return m;
}

std::vector<char> on_faces(const mesh::Mesh& m, const std::vector<mesh::Triangle6>& faces) {
  std::vector<char> on(m.n_nodes(), 0);
  for (const auto& f : faces)
    for (int node : f) on[node] = 1;
  return on;
}

// Independent serial reference: assemble the whole scalar operator with
// Eigen on representative nodes and eliminate the prescribed ones directly.
std::vector<Vector3d> reference_solution(const mesh::Mesh& m, const std::vector<Vector3d>& d_s) {
  const int n = m.n_nodes();
  const auto wall = on_faces(m, m.boundary_faces);
  const auto iface = on_faces(m, m.interface_faces);
  std::vector<int> prescribed(n, 0);  // 0 free, 1 interface, 2 wall
  std::vector<Vector3d> value(n, Vector3d::Zero());
  for (int i = 0; i < n; ++i)
    if (wall[i]) prescribed[m.master(i)] = 2;
  for (int i = 0; i < n; ++i)
    if (iface[i]) {
      prescribed[m.master(i)] = 1;
      value[m.master(i)] = d_s[i];
    }
  std::vector<int> index(n, -1);
  int n_free = 0;
  for (int i = 0; i < n; ++i)
    if (m.master(i) == i && prescribed[i] == 0) index[i] = n_free++;
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n_free, 3);
  const fem::TetTabulation tab(5);
  physics::AleTetMatrix ke;
  for (int t = 0; t < m.n_tets(); ++t) {
    physics::ale_tet_matrix(fem::tet_nodes(m, t), tab, ke);
    for (int a = 0; a < 10; ++a) {
      const int ra = m.master(m.tets[t][a]);
      if (index[ra] < 0) continue;
      for (int b = 0; b < 10; ++b) {
        const int rb = m.master(m.tets[t][b]);
        if (index[rb] >= 0)
          entries.emplace_back(index[ra], index[rb], ke(a, b));
        else
          rhs.row(index[ra]) -= ke(a, b) * value[rb].transpose();
      }
    }
  }
  Eigen::SparseMatrix<double> a(n_free, n_free);
  a.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(a);
  const Eigen::MatrixXd x = ldlt.solve(rhs);
  std::vector<Vector3d> d(n);
  for (int i = 0; i < n; ++i) {
    const int r = m.master(i);
    d[i] = index[r] >= 0 ? Vector3d(x.row(index[r]).transpose()) : value[r];
  }
  return d;
}

double max_difference(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, (a[i] - b[i]).norm());
  return worst;
}

std::vector<Vector3d> translation_on_interface(const mesh::Mesh& m, const Vector3d& t) {
  std::vector<Vector3d> d(m.n_nodes(), Vector3d::Zero());
  for (const auto& f : m.interface_faces)
    for (int node : f) d[node] = t;
  return d;
}

// Checks the translation test's three properties; returns the largest
// overshoot beyond [0, t_c] relative to |t_c|. P2 elements have no
// guaranteed discrete maximum principle, but on these meshes every
// component stays in [0, t_c] to solver tolerance (measured ~1e-11), so the
// callers allow only 1e-6.
double check_translation(const mesh::Mesh& m, const std::vector<Vector3d>& d, const Vector3d& t) {
  const auto iface = on_faces(m, m.interface_faces);
  const auto wall = on_faces(m, m.boundary_faces);
  double overshoot = 0.0;
  for (int i = 0; i < m.n_nodes(); ++i) {
    if (iface[i]) {
      EXPECT_EQ(d[i], t) << "interface node " << i;
    } else if (wall[i]) {
      EXPECT_EQ(d[i], Vector3d::Zero()) << "wall node " << i;
    }
    EXPECT_EQ(d[i], d[m.master(i)]) << "periodic node " << i;
    for (int c = 0; c < 3; ++c) {
      const double lo = std::min(0.0, t(c)), hi = std::max(0.0, t(c));
      overshoot = std::max(overshoot, std::max(lo - d[i](c), d[i](c) - hi) / std::abs(t(c)));
    }
  }
  return overshoot;
}

physics::AleSettings with_method(physics::AleMethod method) {
  physics::AleSettings s;
  s.method = method;
  return s;
}

// Most properties are checked for both solution methods.
class AleMeshMotionMethod : public ::testing::TestWithParam<physics::AleMethod> {
 protected:
  [[nodiscard]] physics::AleSettings settings() const { return with_method(GetParam()); }
};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Methods, AleMeshMotionMethod,
                         ::testing::Values(physics::AleMethod::direct,
                                           physics::AleMethod::iterative),
                         [](const auto& info) {
                           return info.param == physics::AleMethod::direct ? "direct" : "iterative";
                         });

TEST(AleMeshMotion, AutomaticMethodFactorsSmallProblems) {
  EXPECT_EQ(AleMeshMotion(box_with_block()).method(), physics::AleMethod::direct);
}

TEST(AleMeshMotion, ElementMatrixAnnihilatesConstantsAndScalesWithInverseSize) {
  const auto m = mesh::structured_box({2.0, 2.0, 2.0, false, false}, 1, 1, 1);
  const fem::TetTabulation tab(5);
  physics::AleTetMatrix k1, k2;
  auto x = fem::tet_nodes(m, 0);
  const double v1 = physics::ale_tet_matrix(x, tab, k1);
  EXPECT_NEAR(v1, 8.0 / 6.0, 1e-12);
  EXPECT_LT((k1 * Eigen::Matrix<double, 10, 1>::Ones()).norm(), 1e-12);
  EXPECT_LT((k1 - k1.transpose()).norm(), 1e-12);
  // Integral of grad N . grad N scales like h, k_e like h^-3.
  x *= 3.0;
  physics::ale_tet_matrix(x, tab, k2);
  EXPECT_LT((k2 - k1 / 9.0).norm(), 1e-12 * k1.norm());
  // (k_e grad x, grad N) = (1/V) int grad N: the linear field x reproduces it.
  Eigen::Matrix<double, 10, 1> xs = x.row(0).transpose();
  Eigen::Matrix<double, 10, 1> load = k2 * xs;
  EXPECT_NEAR(load.sum(), 0.0, 1e-12);
}

TEST_P(AleMeshMotionMethod, StructuredBoxTranslationMatchesSerialReference) {
  const auto m = box_with_block();
  ASSERT_FALSE(m.interface_faces.empty());
  AleMeshMotion ale(m, settings());
  const Vector3d t(0.1, -0.05, 0.02);
  const auto d_s = translation_on_interface(m, t);
  const auto d = ale.solve(d_s);
  EXPECT_LT(check_translation(m, d, t), 1e-6);
  EXPECT_LT(max_difference(d, reference_solution(m, d_s)), 1e-8 * t.norm());
  EXPECT_GT(ale.last_total_iterations(), 0);
  EXPECT_GT(ale.last_solve_seconds(), 0.0);
  const auto iface = on_faces(m, m.interface_faces);
  EXPECT_EQ(static_cast<long>(ale.interface_nodes().size()),
            static_cast<long>(std::count(iface.begin(), iface.end(), 1)));
}

TEST(AleMeshMotion, DirectAndIterativeAgreeOnAGeneralInterfaceField) {
  const auto m = box_with_block();
  AleMeshMotion iterative_ale(m, with_method(physics::AleMethod::iterative));
  AleMeshMotion direct_ale(m, with_method(physics::AleMethod::direct));
  ASSERT_EQ(iterative_ale.method(), physics::AleMethod::iterative);
  std::vector<Vector3d> d_s(m.n_nodes(), Vector3d::Zero());
  for (int node : iterative_ale.interface_nodes()) {
    const Vector3d& x = m.nodes[node];
    d_s[node] = 0.1 * Vector3d(x.y() * x.z(), std::sin(x.x()), x.x() - x.z());
  }
  const auto reference = reference_solution(m, d_s);
  EXPECT_LT(max_difference(iterative_ale.solve(d_s), reference), 1e-9);
  EXPECT_LT(max_difference(direct_ale.solve(d_s), reference), 1e-11);
  EXPECT_EQ(direct_ale.last_iterations(), (std::array<int, 3>{1, 1, 1}));
}

TEST_P(AleMeshMotionMethod, ZeroInterfaceDisplacementGivesZero) {
  const auto& m = sphere_cell();
  AleMeshMotion ale(m, settings());
  const std::vector<Vector3d> zero(m.n_nodes(), Vector3d::Zero());
  for (const auto& di : ale.solve(zero)) EXPECT_EQ(di, Vector3d::Zero());
  // Also after a nonzero solve, whose solution is the next warm start.
  ale.solve(translation_on_interface(m, Vector3d(0.1, 0.1, 0.1)));
  for (const auto& di : ale.solve(zero)) EXPECT_EQ(di, Vector3d::Zero());
}

TEST_P(AleMeshMotionMethod, SphereTranslationIsExactOnInterfaceZeroOnWallsAndBounded) {
  const auto& m = sphere_cell();
  AleMeshMotion ale(m, settings());
  const Vector3d t(0.05, -0.03, 0.02);
  const auto d_s = translation_on_interface(m, t);
  const auto d = ale.solve(d_s);
  EXPECT_LT(check_translation(m, d, t), 1e-6);
  // Inside the sphere the interface data is constant: the field is t there.
  int inside = 0;
  for (int i = 0; i < m.n_nodes(); ++i)
    if (m.nodes[i].norm() < 0.9) {
      ++inside;
      EXPECT_LT((d[i] - t).norm(), 1e-8 * t.norm());
    }
  EXPECT_GT(inside, 0);
  EXPECT_LT(max_difference(d, reference_solution(m, d_s)), 1e-8 * t.norm());
}

TEST_P(AleMeshMotionMethod, IncrementsAddUpToTheTotalDisplacement) {
  // One reference operator: extending two increments and adding equals
  // extending their sum (what lets the caller pass per-step increments).
  const auto& m = sphere_cell();
  AleMeshMotion ale(m, settings());
  const auto first = ale.solve(translation_on_interface(m, Vector3d(0.02, 0.0, 0.01)));
  const auto second = ale.solve(translation_on_interface(m, Vector3d(0.01, 0.03, 0.0)));
  const auto total = ale.solve(translation_on_interface(m, Vector3d(0.03, 0.03, 0.01)));
  double worst = 0.0;
  for (int i = 0; i < m.n_nodes(); ++i)
    worst = std::max(worst, (first[i] + second[i] - total[i]).norm());
  EXPECT_LT(worst, 1e-10);
}

TEST_P(AleMeshMotionMethod, EllipsoidalStretchKeepsElementsValidAndPeriodicityExact) {
  mesh::Mesh m = sphere_cell();
  const double q0 = mesh::min_quality(m);
  ASSERT_GT(q0, 0.0);
  AleMeshMotion ale(m, settings());
  const double a = 1.1, b = 1.0 / std::sqrt(1.1);
  std::vector<Vector3d> d_s(m.n_nodes(), Vector3d::Zero());
  for (int node : ale.interface_nodes()) {
    const Vector3d& x = m.nodes[node];
    d_s[node] = Vector3d((a - 1) * x.x(), (b - 1) * x.y(), (b - 1) * x.z());
  }
  const auto d = ale.solve(d_s);
  const auto before = m.nodes;
  for (int i = 0; i < m.n_nodes(); ++i) m.nodes[i] += d[i];

  const double q1 = mesh::min_quality(m);
  EXPECT_GT(q1, 0.0);
  EXPECT_GT(q1, 0.5 * q0) << "min quality " << q0 << " -> " << q1;
  // Interface nodes lie on the ellipsoid x^2/a^2 + (y^2 + z^2)/b^2 = 1.
  for (int node : ale.interface_nodes()) {
    const Vector3d& x = m.nodes[node];
    EXPECT_NEAR(x.x() * x.x() / (a * a) + (x.y() * x.y() + x.z() * x.z()) / (b * b), 1.0, 1e-9);
  }
  // Periodic copies keep their lattice offset; walls do not move.
  ASSERT_FALSE(m.periodic_master.empty());
  int periodic = 0;
  for (int i = 0; i < m.n_nodes(); ++i) {
    const int r = m.master(i);
    if (r == i) continue;
    ++periodic;
    const Vector3d offset = m.nodes[i] - m.nodes[r];
    EXPECT_LT((offset - (before[i] - before[r])).norm(), 1e-12);
    EXPECT_NEAR(offset.y(), 0.0, 1e-9);
    EXPECT_NEAR(std::remainder(offset.x(), m.box.length), 0.0, 1e-9);
    EXPECT_NEAR(std::remainder(offset.z(), m.box.width), 0.0, 1e-9);
  }
  EXPECT_GT(periodic, 0);
  for (const auto& f : m.boundary_faces)
    for (int node : f) EXPECT_EQ(m.nodes[node], before[node]);
}

TEST(AleMeshMotion, RejectsAWronglySizedInput) {
  const auto m = box_with_block();
  AleMeshMotion ale(m);
  EXPECT_THROW(ale.solve(std::vector<Vector3d>(3, Vector3d::Zero())), SolverError);
}

TEST(AleMeshMotion, ARestoredWarmStartRepeatsTheUninterruptedSolveExactly) {
  // The iterative method starts each component from its last solution, so a
  // restarted run's mesh agrees with an uninterrupted run's to round-off
  // only if that start is restored with the rest of the state.
  const auto m = box_with_block();
  AleMeshMotion running(m, with_method(physics::AleMethod::iterative));
  auto field = [&](double scale) {
    std::vector<Vector3d> d_s(m.n_nodes(), Vector3d::Zero());
    for (int node : running.interface_nodes()) {
      const Vector3d& x = m.nodes[node];
      d_s[node] = scale * Vector3d(x.y() * x.z(), std::sin(x.x()), x.x() - x.z());
    }
    return d_s;
  };
  running.solve(field(0.1));
  StateRecord record;
  running.save_warm_start(record, "ale_");
  const auto uninterrupted = running.solve(field(0.12));

  AleMeshMotion restarted(m, with_method(physics::AleMethod::iterative));
  restarted.restore_warm_start(record, "ale_");
  EXPECT_EQ(max_difference(restarted.solve(field(0.12)), uninterrupted), 0.0);
  // Without it the start is zero: the same answer only to the CG tolerance.
  AleMeshMotion cold(m, with_method(physics::AleMethod::iterative));
  const double cold_difference = max_difference(cold.solve(field(0.12)), uninterrupted);
  EXPECT_GT(cold_difference, 0.0);
  EXPECT_LT(cold_difference, 1e-8);
  // The direct method keeps nothing.
  AleMeshMotion direct(m, with_method(physics::AleMethod::direct));
  StateRecord none;
  direct.save_warm_start(none, "ale_");
  EXPECT_FALSE(none.contains("ale_warm_start_0"));
}
