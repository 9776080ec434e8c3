#include "softflow/physics/viscoelastic/conformation_transport.hpp"

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/physics/viscoelastic/log_conformation.hpp"

namespace softflow::physics::viscoelastic {

SymmetricPacked pack_symmetric(const Mat3& a) {
  SymmetricPacked v;
  v << a(0, 0), a(1, 1), a(2, 2), a(0, 1), a(1, 2), a(0, 2);
  return v;
}

Mat3 unpack_symmetric(const Eigen::Ref<const Eigen::VectorXd>& v) {
  Mat3 a;
  a << v(0), v(3), v(5),  //
      v(3), v(1), v(4),   //
      v(5), v(4), v(2);
  return a;
}

AleTransport::Source log_conformation_source(const std::vector<Constitutive>& models,
                                             const fem::Field& velocity,
                                             const fem::Field& log_conformation,
                                             const AleTransport& transport) {
  if (log_conformation.components() != kSymmetricComponents || velocity.components() != 3)
    throw Error(fmt::format("log_conformation_source: a 6-component '{}' and a 3-component "
                            "'{}' are needed",
                            log_conformation.name(), velocity.name()));
  return [&models, &velocity, &log_conformation, &transport](const fem::QuadraturePoint& p) {
    const Constitutive& model = models.at(p.region);
    if (!model.has_conformation()) return fem::PointValue(fem::PointValue::Zero(6));
    fem::PointValue s = log_conformation.value(p);
    const auto& e = transport.step_extrapolation();
    if (e.previous != 0.0) s = e.current * s + e.previous * transport.previous().value(p);
    const Mat3 l = velocity.gradient(p);  // row i = grad u_i: L_ij = du_i/dx_j
    return fem::PointValue(pack_symmetric(log_conformation_rate(model, l, unpack_symmetric(s))));
  };
}

}  // namespace softflow::physics::viscoelastic
