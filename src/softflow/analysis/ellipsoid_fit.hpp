// Least-squares ellipsoid through an object's interface nodes: semi-axes, D, theta, shape check.
#pragma once

#include <span>

#include <Eigen/Core>

namespace softflow::analysis {

/// The ellipsoid that best fits a set of surface points (thesis §2.3.4), and
/// how far the points are from it. Flow direction x, shear plane x-y,
/// vorticity along z (u_x = shear rate * y).
struct EllipsoidFit {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  /// Unit semi-axis directions as columns, in the order of semi_axes
  /// (right-handed; the sign of a direction carries no meaning).
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  /// Semi-axis lengths, descending.
  Eigen::Vector3d semi_axes = Eigen::Vector3d::Ones();
  /// W is the semi-axis whose direction lies closest to z (vorticity); L >= B
  /// are the other two, the ones in (or nearest to) the shear plane.
  double L = 1.0, B = 1.0, W = 1.0;
  /// Taylor deformation parameter D = (L - B) / (L + B).
  double deformation = 0.0;
  /// Angle of the L direction, projected on the x-y plane, with the flow
  /// direction x, measured towards +y, in (-90, 90] degrees. A drop in
  /// u_x = shear rate * y settles at +45 degrees minus O(Ca) (eq. 2.59).
  /// Meaningless when L ~ B (D ~ 0): the direction of L is then arbitrary.
  double theta_deg = 0.0;
  /// Largest distance of a point to the fitted surface (true closest-point
  /// distance, not the algebraic residual) over the mean radius (abc)^{1/3}.
  /// The thesis calls a shape ellipsoidal below 0.02-0.03.
  double max_relative_deviation = 0.0;
};

/// Fits a x^2 + b y^2 + c z^2 + d xy + e xz + f yz + g x + h y + i z = 1
/// (eq. 2.57) to `points` by linear least squares and reduces the quadric to
/// centre, axes and semi-axes. Throws softflow::Error for fewer than 9
/// points, points that do not determine a quadric (e.g. all on one plane or
/// circle), or a fitted quadric that is not a real ellipsoid. A non-
/// ellipsoidal but closed point cloud (a cube, a dumbbell) is still fitted;
/// max_relative_deviation is what tells it apart.
EllipsoidFit fit_ellipsoid(std::span<const Eigen::Vector3d> points);

/// Distance from `point` to the surface of the ellipsoid with the given
/// centre, axes (unit columns) and semi-axes (descending): the length of the
/// segment to the closest surface point, for points inside or outside.
double distance_to_ellipsoid(const Eigen::Vector3d& point, const Eigen::Vector3d& centre,
                             const Eigen::Matrix3d& axes, const Eigen::Vector3d& semi_axes);

}  // namespace softflow::analysis
