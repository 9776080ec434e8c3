#include "softflow/fem/field.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>
#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/la/csr_matrix.hpp"
#include "softflow/la/vector_values.hpp"

namespace softflow::fem {

using la::check;

std::vector<int> owned_elements(const mesh::Mesh& mesh) {
  const auto [begin, end] = rank_node_range(mesh.n_nodes(), la::mpi_rank(), la::mpi_size());
  std::vector<int> owned;
  for (int t = 0; t < mesh.n_tets(); ++t) {
    const long node = mesh.master(mesh.tets[t][0]);
    if (node >= begin && node < end) owned.push_back(t);
  }
  return owned;
}

std::vector<int> elements_touching(const mesh::Mesh& mesh, int first_node, int last_node) {
  std::vector<int> touching;
  for (int t = 0; t < mesh.n_tets(); ++t)
    for (int node : mesh.tets[t]) {
      const int rep = mesh.master(node);
      if (rep >= first_node && rep < last_node) {
        touching.push_back(t);
        break;
      }
    }
  return touching;
}

std::vector<QuadraturePoint> quadrature_points(const mesh::Mesh& mesh, const TetTabulation& tab,
                                               int tet) {
  const auto x = tet_nodes(mesh, tet);
  std::vector<QuadraturePoint> points(tab.rule.size());
  for (int q = 0; q < tab.rule.size(); ++q) {
    QuadraturePoint& p = points[q];
    p.tab = &tab;
    p.tet = tet;
    p.region = mesh.tet_region[tet];
    p.q = q;
    p.map = element::tet_map(x, tab.p2_grad[q]);
    p.weight = tab.rule.weights[q] * p.map.det_jacobian;
    for (int k = 0; k < 10; ++k) p.x += tab.p2[q][k] * x.col(k);
  }
  return points;
}

namespace {

/// Values at points have room for kMaxFieldComponents (field.hpp).
int checked_components(const std::string& name, int components) {
  if (components < 1 || components > kMaxFieldComponents)
    throw Error(fmt::format("Field '{}': {} components; a field has 1 to {} (a full tensor)", name,
                            components, kMaxFieldComponents));
  return components;
}

}  // namespace

Field::Field(const mesh::Mesh& mesh, std::string name, std::shared_ptr<const Space> space,
             int components)
    : mesh_(mesh),
      name_(std::move(name)),
      dofs_(mesh, {{name_, std::move(space), checked_components(name_, components)}}) {
  if (this->space().n_element_nodes() > 10)
    throw Error(fmt::format("Field '{}': a space of {} nodes per element; at most 10 (P2)", name_,
                            this->space().n_element_nodes()));
  // The node range every dof map uses: every field then has the same node
  // ranges, so a scalar operator of the space can be solved once and copied
  // into each component locally, and its elements are this rank's own.
  const auto [first, last] = rank_node_range(mesh_.n_nodes(), la::mpi_rank(), la::mpi_size());
  range_ = {dofs_.dof_offset_of_node(first), dofs_.dof_offset_of_node(last)};
  owned_elements_ = fem::owned_elements(mesh_);
  std::vector<int> ghosts;
  for (int t : elements_touching(mesh_, first, last))
    for (int dof : dofs_.element_dofs(t))
      if (!range_.owns(dof)) ghosts.push_back(dof);
  std::sort(ghosts.begin(), ghosts.end());
  ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());

  local_index_.assign(dofs_.n_dofs(), -1);
  for (int d = range_.begin; d < range_.end; ++d) local_index_[d] = d - range_.begin;
  for (std::size_t g = 0; g < ghosts.size(); ++g)
    local_index_[ghosts[g]] = range_.size() + static_cast<int>(g);

  std::vector<PetscInt> ghost_indices(ghosts.begin(), ghosts.end());
  check(VecCreateGhost(PETSC_COMM_WORLD, range_.size(), dofs_.n_dofs(),
                       static_cast<PetscInt>(ghost_indices.size()), ghost_indices.data(),
                       vector_.out()),
        "VecCreateGhost");
  check(VecSet(vector_.get(), 0.0), "VecSet");
  local_.assign(range_.size() + ghosts.size(), 0.0);
}

void Field::update_ghosts() {
  check(VecGhostUpdateBegin(vector_.get(), INSERT_VALUES, SCATTER_FORWARD), "VecGhostUpdateBegin");
  check(VecGhostUpdateEnd(vector_.get(), INSERT_VALUES, SCATTER_FORWARD), "VecGhostUpdateEnd");
  Vec local = nullptr;
  check(VecGhostGetLocalForm(vector_.get(), &local), "VecGhostGetLocalForm");
  const PetscScalar* a = nullptr;
  check(VecGetArrayRead(local, &a), "VecGetArrayRead");
  std::copy(a, a + local_.size(), local_.begin());
  check(VecRestoreArrayRead(local, &a), "VecRestoreArrayRead");
  check(VecGhostRestoreLocalForm(vector_.get(), &local), "VecGhostRestoreLocalForm");
}

void Field::interpolate(
    const std::function<Eigen::VectorXd(const Eigen::Vector3d&, int region)>& f) {
  const int n_c = components();
  PetscScalar* a = nullptr;
  check(VecGetArray(vector_.get(), &a), "VecGetArray");
  // Components of one copy are contiguous: one evaluation per copy.
  for (int d = range_.begin; d < range_.end; d += n_c) {
    const Eigen::VectorXd v = f(mesh_.nodes[dofs_.node_of(d)], dofs_.region_of(d));
    if (v.size() != n_c)
      throw SolverError(fmt::format("Field '{}': interpolated function has {} components, not {}",
                                    name_, v.size(), n_c));
    for (int c = 0; c < n_c; ++c) a[d - range_.begin + c] = v(c);
  }
  check(VecRestoreArray(vector_.get(), &a), "VecRestoreArray");
  update_ghosts();
}

void Field::check_source(const DofMap& source, int field) const {
  if (source.field(field).components != components() ||
      source.field(field).space->n_dofs() != space().n_dofs())
    throw SolverError(fmt::format("Field '{}': source field '{}' has another space", name_,
                                  source.field(field).name));
}

void Field::assign_from(const DofMap& source, int field, std::span<const double> values) {
  check_source(source, field);
  PetscScalar* a = nullptr;
  check(VecGetArray(vector_.get(), &a), "VecGetArray");
  for (int d = range_.begin; d < range_.end; ++d)
    a[d - range_.begin] = values[source.dof(field, dofs_.node_of(d), dofs_.region_of(d),
                                            dofs_.component_of(d))];
  check(VecRestoreArray(vector_.get(), &a), "VecRestoreArray");
  update_ghosts();
}

void Field::assign_from(const DofMap& source, int field, Vec values) {
  check_source(source, field);
  PetscInt begin = 0, end = 0;
  check(VecGetOwnershipRange(values, &begin, &end), "VecGetOwnershipRange");
  const PetscScalar* from = nullptr;
  PetscScalar* a = nullptr;
  check(VecGetArrayRead(values, &from), "VecGetArrayRead");
  check(VecGetArray(vector_.get(), &a), "VecGetArray");
  // Both maps number node range by node range (fem::rank_node_range): the
  // source dof of an owned dof is owned here too, and no value crosses ranks.
  int misplaced = -1;
  for (int d = range_.begin; d < range_.end && misplaced < 0; ++d) {
    const int s = source.dof(field, dofs_.node_of(d), dofs_.region_of(d), dofs_.component_of(d));
    if (s < begin || s >= end) misplaced = d;
    else a[d - range_.begin] = from[s - begin];
  }
  check(VecRestoreArray(vector_.get(), &a), "VecRestoreArray");
  check(VecRestoreArrayRead(values, &from), "VecRestoreArrayRead");
  if (misplaced >= 0)
    throw SolverError(fmt::format("Field '{}': the source's value of dof {} (node {}) is on "
                                  "another rank: the two dof maps split the nodes differently",
                                  name_, misplaced, dofs_.node_of(misplaced)));
  update_ghosts();
}

std::vector<double> Field::gather() const { return la::gather_to_all(vector_.get()); }

void Field::scatter(std::span<const double> all) {
  if (static_cast<int>(all.size()) != dofs_.n_dofs())
    throw SolverError(fmt::format("Field '{}': {} values for {} dofs", name_, all.size(),
                                  dofs_.n_dofs()));
  la::scatter_from_all(vector_.get(), all);
  update_ghosts();
}

ElementCoefficients Field::element_coefficients(int tet) const {
  const auto d = dofs_.element_dofs(tet);
  ElementCoefficients c(d.size());
  for (std::size_t i = 0; i < d.size(); ++i) {
    const int l = local_index(d[i]);
    if (l < 0)
      throw SolverError(fmt::format("Field '{}': element {} is not on this rank", name_, tet));
    c(static_cast<Eigen::Index>(i)) = local_[l];
  }
  return c;
}

namespace {

// Shape-function values of a space of degree p at a quadrature point.
std::span<const double> shape_values(const TetTabulation& tab, int q, int degree) {
  if (degree == 2) return tab.p2[q];
  return tab.p1[q];
}

}  // namespace

PointValue Field::value(const QuadraturePoint& p) const {
  const int n_c = components(), n_k = space().n_element_nodes();
  const ElementCoefficients c = element_coefficients(p.tet);
  const auto n = shape_values(*p.tab, p.q, space().degree());
  PointValue v = PointValue::Zero(n_c);
  for (int k = 0; k < n_k; ++k) v += n[k] * c.segment(k * n_c, n_c);
  return v;
}

PointGradient Field::gradient(const QuadraturePoint& p) const {
  const int n_c = components(), n_k = space().n_element_nodes();
  const ElementCoefficients c = element_coefficients(p.tet);
  // grad N = (grad_xi N) J^{-1}, one row per function.
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::ColMajor, 10, 3> g;
  if (space().degree() == 2) {
    g = p.tab->p2_grad[p.q] * p.map.inverse_jacobian;
  } else {
    g = element::p1_tet_gradients() * p.map.inverse_jacobian;
  }
  PointGradient out = PointGradient::Zero(n_c, 3);
  for (int k = 0; k < n_k; ++k)
    for (int comp = 0; comp < n_c; ++comp) out.row(comp) += c(k * n_c + comp) * g.row(k);
  return out;
}

PointValue Field::value_at_reference(int tet, const Eigen::Vector3d& xi) const {
  const int n_c = components();
  const ElementCoefficients c = element_coefficients(tet);
  PointValue v = PointValue::Zero(n_c);
  if (space().degree() == 2) {
    const auto n = element::p2_tet_values(xi);
    for (int k = 0; k < 10; ++k) v += n[k] * c.segment(k * n_c, n_c);
  } else {
    const auto n = element::p1_tet_values(xi);
    for (int k = 0; k < 4; ++k) v += n[k] * c.segment(k * n_c, n_c);
  }
  return v;
}

std::optional<Field::Location> Field::locate(const Eigen::Vector3d& x, double tolerance) const {
  for (int t : owned_elements_) {
    const auto nodes = tet_nodes(mesh_, t);
    const Eigen::Vector3d lo = nodes.rowwise().minCoeff(), hi = nodes.rowwise().maxCoeff();
    const double slack = 1e-8 * (hi - lo).norm();
    if ((x.array() < lo.array() - slack).any() || (x.array() > hi.array() + slack).any()) continue;
    // Newton on x(xi) = x: the curved map is quadratic in xi.
    Eigen::Vector3d xi(0.25, 0.25, 0.25);
    for (int it = 0; it < 30; ++it) {
      const auto n = element::p2_tet_values(xi);
      Eigen::Vector3d r = -x;
      for (int k = 0; k < 10; ++k) r += n[k] * nodes.col(k);
      const Eigen::Matrix3d j = nodes * element::p2_tet_gradients(xi);
      const Eigen::Vector3d step = j.partialPivLu().solve(r);
      xi -= step;
      if (step.norm() < 1e-14) break;
    }
    if (xi.minCoeff() >= -tolerance && xi.sum() <= 1.0 + tolerance) return Location{t, xi};
  }
  return std::nullopt;
}

std::optional<Eigen::VectorXd> Field::value_at_point(const Eigen::Vector3d& x) const {
  const auto where = locate(x);
  if (!where) return std::nullopt;
  return value_at_reference(where->tet, where->xi);
}

ElementMatrix element_matrix(const Field& field) {
  const auto range = field.ownership();
  const la::OwnershipRange rows{range.begin, range.end};
  const int n = field.dofs().n_dofs();
  ElementMatrix m{std::make_unique<la::CsrMatrix>(rows, n, rows, n), {}};
  for (int t : field.owned_elements())
    m.blocks.push_back(m.matrix->add_block(field.dofs().element_dofs(t), field.dofs().element_dofs(t)));
  m.matrix->create();
  return m;
}

void Field::save(StateRecord& record, const std::string& key, int columns) const {
  la::save_vector(record, key, vector_.get(), columns);
}

void Field::restore(const StateRecord& record, const std::string& key, int columns) {
  la::restore_vector(record, key, vector_.get(), fmt::format("field '{}'", name_), columns);
  update_ghosts();
}

StatePart state_part(Field& field) {
  return {"fields/" + field.name(),
          [&field](StateRecord& r, const std::string& p) { field.save(r, p + "values"); },
          [&field](const StateRecord& r, const std::string& p) { field.restore(r, p + "values"); }};
}

void l2_project(const std::function<Eigen::VectorXd(const QuadraturePoint&)>& f, Field& target,
                int quadrature_degree) {
  // The mass matrix is the same for every component: assemble it once on
  // the scalar space (one dof per node copy) and solve per component, as
  // AleTransport does, instead of a block-diagonal matrix n_c times larger.
  const TetTabulation tab(quadrature_degree);
  Field scalar(target.mesh(), target.name() + "_component", target.dofs().field(0).space, 1);
  const DofMap& dofs = scalar.dofs();
  const int n_c = target.components(), n_k = target.space().n_element_nodes();
  const auto range = scalar.ownership();
  auto mass = element_matrix(scalar);

  std::vector<la::Vector> rhs(n_c);
  for (auto& b : rhs) {
    b = la::make_vector(range.size(), dofs.n_dofs());
    check(VecSet(b.get(), 0.0), "VecSet");
  }
  Eigen::MatrixXd me(n_k, n_k), fe(n_k, n_c);
  Eigen::VectorXd phi(n_k);
  std::size_t e = 0;
  for (int t : target.owned_elements()) {
    me.setZero();
    fe.setZero();
    for (const auto& p : quadrature_points(target.mesh(), tab, t)) {
      const auto values = shape_values(tab, p.q, target.space().degree());
      for (int a = 0; a < n_k; ++a) phi(a) = values[a];
      me.noalias() += p.weight * phi * phi.transpose();
      fe.noalias() += p.weight * phi * f(p).transpose();
    }
    mass.matrix->set_block(mass.blocks[e++], me);
    const auto d = dofs.element_dofs(t);
    for (int c = 0; c < n_c; ++c) {
      const Eigen::VectorXd column = fe.col(c);
      check(VecSetValues(rhs[c].get(), n_k, d.data(), column.data(), ADD_VALUES), "VecSetValues");
    }
  }
  mass.matrix->assemble();
  for (auto& b : rhs) {
    check(VecAssemblyBegin(b.get()), "VecAssemblyBegin");
    check(VecAssemblyEnd(b.get()), "VecAssemblyEnd");
  }

  la::Solver ksp;
  check(KSPCreate(PETSC_COMM_WORLD, ksp.out()), "KSPCreate");
  check(KSPSetOperators(ksp.get(), mass.matrix->get(), mass.matrix->get()), "KSPSetOperators");
  check(KSPSetType(ksp.get(), KSPCG), "KSPSetType");
  PC pc = nullptr;
  check(KSPGetPC(ksp.get(), &pc), "KSPGetPC");
  // The consistent mass matrix is spectrally equivalent to its diagonal:
  // Jacobi-CG converges in a mesh-independent number of iterations.
  check(PCSetType(pc, PCJACOBI), "PCSetType");
  check(KSPSetTolerances(ksp.get(), 1e-12, 0.0, PETSC_DEFAULT, 1000), "KSPSetTolerances");
  solve_by_component(ksp.get(), rhs, scalar, target, "L2 projection onto '" + target.name() + "'");
  target.update_ghosts();
}

void solve_by_component(KSP ksp, std::span<const la::Vector> rhs, Field& scalar, Field& target,
                        const std::string& what) {
  const int n_c = target.components();
  if (static_cast<int>(rhs.size()) != n_c || scalar.components() != 1)
    throw Error(fmt::format("solve_by_component: {} right-hand sides for {} components", rhs.size(), n_c));
  const auto range = scalar.ownership();
  for (int c = 0; c < n_c; ++c) {
    check(KSPSolve(ksp, rhs[c].get(), scalar.vector()), "KSPSolve");
    KSPConvergedReason reason;
    check(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
    if (reason < 0)
      throw SolverError(fmt::format("{} failed: {}", what, KSPConvergedReasons[reason]));
    // The same node ranges (one field each): owned scalar dof i is owned
    // component dof i * n_c + c.
    PetscScalar* out = nullptr;
    const PetscScalar* in = nullptr;
    check(VecGetArray(target.vector(), &out), "VecGetArray");
    check(VecGetArrayRead(scalar.vector(), &in), "VecGetArrayRead");
    for (int i = 0; i < range.size(); ++i) out[i * n_c + c] = in[i];
    check(VecRestoreArrayRead(scalar.vector(), &in), "VecRestoreArrayRead");
    check(VecRestoreArray(target.vector(), &out), "VecRestoreArray");
  }
}

}  // namespace softflow::fem
