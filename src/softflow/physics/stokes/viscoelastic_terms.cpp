#include "softflow/physics/stokes/viscoelastic_terms.hpp"

#include <array>

#include "softflow/physics/viscoelastic/conformation_prediction.hpp"
#include "softflow/physics/viscoelastic/constitutive_law.hpp"
#include "softflow/physics/viscoelastic/conformation_transport.hpp"

namespace softflow::physics {

namespace ve = viscoelastic;

double ViscoelasticCoupling::devss_theta(int region) const {
  const auto& model = models.at(region);
  if (!velocity_gradient || !model.has_conformation()) return 0.0;
  return model.relaxes() ? model.polymer_viscosity() : model.modulus() * dt;
}

double ViscoelasticCoupling::step_viscosity(int region) const {
  const auto& model = models.at(region);
  if (!model.has_conformation()) return model.solvent_viscosity();
  return model.solvent_viscosity() + devss_theta(region) + model.modulus() * dt;
}

PointPrediction predict_at(const ViscoelasticCoupling& coupling, const fem::QuadraturePoint& p) {
  const auto& model = coupling.models.at(p.region);
  const auto& bdf = coupling.bdf;
  const auto& e = coupling.extrapolation;
  const fem::PointValue c_n = coupling.conformation->value(p);
  fem::PointValue extrapolated = e.current * c_n;
  fem::PointValue history = -(bdf.a1 / bdf.a0) * c_n;
  fem::PointGradient grad_c_components = e.current * coupling.conformation->gradient(p);  // 6 x 3
  if (coupling.previous_conformation && (bdf.a2 != 0.0 || e.previous != 0.0)) {
    const fem::PointValue c_previous = coupling.previous_conformation->value(p);
    extrapolated += e.previous * c_previous;
    history -= (bdf.a2 / bdf.a0) * c_previous;
    grad_c_components += e.previous * coupling.previous_conformation->gradient(p);
  }
  std::array<ve::Mat3, 3> grad_c;
  for (int d = 0; d < 3; ++d) grad_c[d] = ve::unpack_symmetric(grad_c_components.col(d));
  // Only the mesh's own motion stays explicit: u.grad c* is in the matrix.
  const Eigen::Vector3d um = coupling.mesh_velocity
                                 ? Eigen::Vector3d(coupling.mesh_velocity->value(p))
                                 : Eigen::Vector3d::Zero();
  const ve::Mat3 c = ve::unpack_symmetric(extrapolated);
  ve::Mat3 h = ve::unpack_symmetric(history);
  if (coupling.defect && coupling.defect->holds(p.tet))
    h += coupling.defect_scale * coupling.defect->get(p.tet, p.q);
  return {c, grad_c,
          ve::ConformationPrediction(model, h, c, ve::convective_derivative(-um, grad_c),
                                     bdf.theta_dt(coupling.dt))};
}

ve::Mat3 predicted_conformation(const ViscoelasticCoupling& coupling, const fem::QuadraturePoint& p,
                                const Eigen::Vector3d& u, const ve::Mat3& velocity_gradient) {
  const PointPrediction point = predict_at(coupling, p);
  return point.prediction(velocity_gradient) -
         coupling.bdf.theta_dt(coupling.dt) * ve::convective_derivative(u, point.gradient);
}

void add_viscoelastic_tet_terms(const ViscoelasticCoupling& coupling,
                                const std::vector<fem::QuadraturePoint>& points, TetMatrix& matrix,
                                TetVector& load) {
  const int region = points.front().region;
  const auto& model = coupling.models.at(region);
  const auto& law = model.law();
  const double theta = coupling.devss_theta(region);
  const double dt = coupling.dt;
  for (const auto& p : points) {
    const Eigen::Matrix<double, 10, 3> g =
        element::physical_gradients<10>(p.tab->p2_grad[p.q], p.map);
    const auto& n = p.tab->p2[p.q];
    const PointPrediction point = predict_at(coupling, p);
    const ve::Mat3& c = point.extrapolated;
    const auto& grad_c = point.gradient;
    const auto& bdf = coupling.bdf;
    const ve::ConformationPrediction& prediction = point.prediction;
    const double w = p.weight;
    // tau at the prediction, linearised at c_n (exact for a stress affine
    // in c): tau(c_n) + tau'(c_n)[dc], tau'(c_n)[dc] = A dc + tr(dc) B.
    const ve::StressDerivative derivative = law.stress_derivative(c);

    // Matrix. For v = N_k e_a and u = N_l e_b (L = e_b (x) grad N_l), the
    // prediction's velocity part dc = dt (L c + c L^T - u.grad c) gives
    //   D(v) : (L c + c L^T) = 2 D(v) : (L c) = delta_ab g_k.(c g_l) + g_k,b (c g_l)_a,
    //   D(v) : (u.grad c)    = N_l (dc/dx_b g_k)_a,
    // and with a trace part also tr(dc) = dt (2 (c g_l)_b - N_l tr(dc/dx_b)),
    //   D(v) : B = (B g_k)_a.
    const Eigen::Matrix<double, 10, 3> cg = g * c;  // row l: (c g_l)^T, c symmetric
    const Eigen::Matrix<double, 10, 10> gcg = g * cg.transpose();
    const double scale = derivative.scale * bdf.theta_dt(dt) * w;
    for (int k = 0; k < 10; ++k) {
      Eigen::Matrix3d convection;  // column b: dc/dx_b g_k
      for (int b = 0; b < 3; ++b) convection.col(b) = grad_c[b] * g.row(k).transpose();
      for (int l = 0; l < 10; ++l)
        for (int b = 0; b < 3; ++b)
          for (int a = 0; a < 3; ++a) {
            double entry = g(k, b) * cg(l, a) - n[l] * convection(a, b);
            if (a == b) entry += gcg(k, l);
            matrix(3 * k + a, 3 * l + b) += scale * entry;
          }
    }
    if (derivative.has_trace_part) {
      const Eigen::Matrix<double, 10, 3> bg = g * derivative.trace_part;  // row k: (B g_k)^T
      Eigen::Vector3d trace_gradient;  // tr(dc/dx_b)
      for (int b = 0; b < 3; ++b) trace_gradient(b) = grad_c[b].trace();
      const double trace_scale = bdf.theta_dt(dt) * w;
      for (int k = 0; k < 10; ++k)
        for (int l = 0; l < 10; ++l)
          for (int b = 0; b < 3; ++b) {
            const double trace = 2.0 * cg(l, b) - n[l] * trace_gradient(b);
            for (int a = 0; a < 3; ++a)
              matrix(3 * k + a, 3 * l + b) += trace_scale * trace * bg(k, a);
          }
    }

    // Load: D(v) : A = (sym(A) g_k)_a for v = N_k e_a.
    const ve::Mat3 stress = law.linearized_stress(c, prediction.constant());
    ve::Mat3 rhs = -stress;
    if (theta > 0.0) {
      const Eigen::VectorXd gv = coupling.velocity_gradient->value(p);
      const ve::Mat3 g_n = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(gv.data());
      rhs += theta * (g_n + g_n.transpose());
    }
    for (int k = 0; k < 10; ++k) load.segment<3>(3 * k) += w * (rhs * g.row(k).transpose());
  }
}

}  // namespace softflow::physics
