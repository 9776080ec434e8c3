// The elastic solids of the particles (thesis §2.2.2, eqs. 2.20-2.22): the
// liquid's conformation equation in the limit lambda -> infinity, c_UC = 0,
// so that c is the Finger tensor B (from c = I at rest, eq. 2.20) and
//
//   tau = G (B - I)  (eq. 2.22),   r(c) = 0  (eq. 2.21).
//
// neo-Hookean: T = tau; Kelvin-Voigt: T = 2 mu D + tau, mu > 0.
#include <limits>
#include <memory>

#include "softflow/physics/viscoelastic/constitutive_law.hpp"

namespace softflow::physics::viscoelastic {

namespace {

class ElasticSolidLaw final : public ConstitutiveLaw {
 public:
  ElasticSolidLaw(ConstitutiveModel model, double mu, double g) : model_(model), mu_(mu), g_(g) {}

  ConstitutiveModel model() const override { return model_; }
  ConstitutiveValues values() const override {
    ConstitutiveValues v{.modulus = g_};
    if (model_ == ConstitutiveModel::kelvin_voigt) v.solvent_viscosity = mu_;
    return v;
  }
  double solvent_viscosity() const override { return mu_; }
  double modulus() const override { return g_; }
  double relaxation_time() const override { return std::numeric_limits<double>::infinity(); }
  bool relaxes() const override { return false; }

  Mat3 polymer_stress(const Mat3& c) const override { return g_ * (c - Mat3::Identity()); }
  Mat3 relaxation(const Mat3& /*c*/) const override { return Mat3::Zero(); }  // eq. 2.21
  Vec3 log_relaxation(const Vec3& /*sigma*/) const override { return Vec3::Zero(); }

 private:
  ConstitutiveModel model_;
  double mu_, g_;
};

}  // namespace

ConstitutiveLawPtr make_elastic_solid_law(ConstitutiveModel model, const ConstitutiveValues& v) {
  const ParameterCheck check(model);
  const char* solid = "an elastic solid is the limit lambda -> infinity";
  check.absent({v.relaxation_time, "relaxation time lambda"}, solid);
  check.absent({v.polymer_viscosity, "polymer viscosity eta_p"},
               "an elastic solid's G lambda is infinite; give the modulus G");
  const Parameter mu{v.solvent_viscosity, "solvent viscosity mu"};
  double solvent = 0.0;
  if (model == ConstitutiveModel::neo_hookean)
    check.absent(mu, "the neo-Hookean solid has mu = 0; use kelvin_voigt", true);
  else
    solvent = check.positive(mu);  // mu = 0 is the neo-Hookean solid
  return std::make_shared<ElasticSolidLaw>(model, solvent,
                                           check.positive({v.modulus, "modulus G"}));
}

}  // namespace softflow::physics::viscoelastic
