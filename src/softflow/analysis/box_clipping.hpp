// The part of a tetrahedron inside an axis-aligned box, as tetrahedra: for
// averages over a sub-box of the mesh (the emulsion's bulk stress, eq. 4.1)
// that do not depend on how the elements happen to meet the box's faces.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "softflow/element/isoparametric.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"

namespace softflow::analysis {

using Tetrahedron = std::array<Eigen::Vector3d, 4>;

/// An axis-aligned box [lo, hi].
struct Box {
  Eigen::Vector3d lo, hi;
  [[nodiscard]] bool contains(const Eigen::Vector3d& x) const {
    return (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
  }
  [[nodiscard]] double volume() const { return (hi - lo).prod(); }
};

/// The cube of side `side` centred at the origin.
Box centred_cube(double side);

/// tet ∩ {x : n.x <= c}, as tetrahedra (none, the tet itself, one corner
/// tetrahedron, or a triangular prism split into three). The vertices of
/// the pieces are the tet's own and the points where its edges cross the
/// plane; a vertex on the plane counts as inside.
std::vector<Tetrahedron> clip_to_half_space(const Tetrahedron& tet, const Eigen::Vector3d& n,
                                            double c);

/// tet ∩ box as tetrahedra: the tet clipped by the box's six faces in turn.
/// Exact for straight-sided tetrahedra (the pieces tile the intersection);
/// empty when they do not meet.
std::vector<Tetrahedron> clip_to_box(const Tetrahedron& tet, const Box& box);

/// The part inside `box` of the curved P2 tetrahedron with nodes x (one per
/// column, its 4 vertices first), as tetrahedra in the element's reference
/// coordinates, ready for a quadrature of any field on the element:
/// {the reference tetrahedron} when all 10 nodes lie in the box, none when
/// the nodes' bounding box misses it, else the straight-sided vertex
/// tetrahedron clipped (clip_to_box) and mapped back by its affine map
/// (exact for straight elements; the curved ones are met only where an
/// interface crosses a face of the box).
std::vector<Tetrahedron> reference_pieces_in_box(const Eigen::Matrix<double, 3, 10>& x, const Box& box);

/// The reference tetrahedron (0, e_x, e_y, e_z): an element taken whole.
Tetrahedron reference_tetrahedron();

/// Calls visit(xi, weight, grad) at each point of `rule` mapped onto each
/// piece (reference coordinates, as reference_pieces_in_box gives them) of
/// the curved P2 tetrahedron with nodes x: xi the reference point, weight
/// its share of the physical volume, grad the physical gradients of the 10
/// P2 functions there (one per row). The pieces' quadrature shared by the
/// averages over a box (the time domain's bulk stress, the frequency
/// domain's cube).
template <class Visit>
void for_each_point_in_pieces(const element::TetNodes& x, const std::vector<Tetrahedron>& pieces,
                              const element::QuadratureRule& rule, Visit&& visit) {
  for (const auto& piece : pieces) {
    Eigen::Matrix3d sub;
    sub << piece[1] - piece[0], piece[2] - piece[0], piece[3] - piece[0];
    const double sub_det = std::abs(sub.determinant());
    if (sub_det == 0.0) continue;
    for (int q = 0; q < rule.size(); ++q) {
      const Eigen::Vector3d xi = piece[0] + sub * rule.points[q];
      const Eigen::Matrix<double, 10, 3> reference_gradients = element::p2_tet_gradients(xi);
      const auto map = element::tet_map(x, reference_gradients);
      const Eigen::Matrix<double, 10, 3> grad = reference_gradients * map.inverse_jacobian;
      visit(xi, rule.weights[q] * sub_det * std::abs(map.det_jacobian), grad);
    }
  }
}

/// |det| / 6 of a tetrahedron.
double tetrahedron_volume(const Tetrahedron& tet);

}  // namespace softflow::analysis
