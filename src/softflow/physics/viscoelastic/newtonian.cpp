// The Newtonian phase, T = 2 eta D (thesis eq. 2.4): no conformation tensor.
// Its viscosity is reported as the solvent viscosity, so that T = 2 mu D + tau
// holds for every phase with tau = 0.
#include <memory>

#include "softflow/common/error.hpp"
#include "softflow/physics/viscoelastic/constitutive_law.hpp"

namespace softflow::physics::viscoelastic {

namespace {

class NewtonianLaw final : public ConstitutiveLaw {
 public:
  explicit NewtonianLaw(double viscosity) : viscosity_(viscosity) {}

  ConstitutiveModel model() const override { return ConstitutiveModel::newtonian; }
  ConstitutiveValues values() const override { return {.viscosity = viscosity_}; }
  double solvent_viscosity() const override { return viscosity_; }
  double modulus() const override { return 0.0; }
  double relaxation_time() const override { return 0.0; }
  bool has_conformation() const override { return false; }
  bool relaxes() const override { return false; }

  Mat3 polymer_stress(const Mat3& /*c*/) const override { return Mat3::Zero(); }
  Mat3 relaxation(const Mat3& /*c*/) const override { throw no_conformation(); }
  Vec3 log_relaxation(const Vec3& /*sigma*/) const override { throw no_conformation(); }

 private:
  static Error no_conformation() {
    return Error("a Newtonian phase has no conformation tensor");
  }
  double viscosity_;
};

}  // namespace

ConstitutiveLawPtr make_newtonian_law(ConstitutiveModel model, const ConstitutiveValues& v) {
  const ParameterCheck check(model);
  for (const Parameter p : {Parameter{v.solvent_viscosity, "solvent viscosity mu"},
                            Parameter{v.modulus, "modulus G"},
                            Parameter{v.polymer_viscosity, "polymer viscosity eta_p"},
                            Parameter{v.relaxation_time, "relaxation time lambda"}})
    check.absent(p, "a Newtonian phase has the viscosity eta only");
  return std::make_shared<NewtonianLaw>(check.positive({v.viscosity, "viscosity eta"}));
}

}  // namespace softflow::physics::viscoelastic
