// The log-conformation tensor as a transported field: its storage as six
// components and the source of its transport equation (SPEC §2 part 5).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "softflow/fem/field.hpp"
#include "softflow/physics/transport/ale_transport.hpp"
#include "softflow/physics/viscoelastic/constitutive.hpp"
#include "softflow/physics/viscoelastic/symmetric_tensor.hpp"

namespace softflow::physics::viscoelastic {

/// Components of a symmetric tensor in a field: xx, yy, zz, xy, yz, xz
/// (the order ParaView reads six-component symmetric tensors in).
inline constexpr int kSymmetricComponents = 6;
using SymmetricPacked = Eigen::Matrix<double, kSymmetricComponents, 1>;
[[nodiscard]] SymmetricPacked pack_symmetric(const Mat3& a);
/// From any contiguous six entries (a field's value at a point, a column of its gradient).
[[nodiscard]] Mat3 unpack_symmetric(const Eigen::Ref<const Eigen::VectorXd>& v);

/// The source r of the log-conformation transport
///
///   ds/dt|_mesh + (u - u_m) . grad s = (Omega s - s Omega) + 2 B + g(s)/lambda
///
/// at a quadrature point (log_conformation_rate): L = grad u of `velocity`
/// (the velocity of the step just solved, u_{n+1}), and s extrapolated to
/// t_{n+1} (AleTransport::step_extrapolation: 2 s_n - s_{n-1} at a constant
/// step, s_n at the first, BDF1, step), so that the explicit source keeps
/// BDF2's second order. `models[region]` is each region's constitutive model; regions
/// without a conformation (Newtonian) get r = 0. The fields and models are
/// referenced, not copied.
[[nodiscard]] AleTransport::Source log_conformation_source(
    const std::vector<Constitutive>& models, const fem::Field& velocity,
    const fem::Field& log_conformation, const AleTransport& transport);

}  // namespace softflow::physics::viscoelastic
