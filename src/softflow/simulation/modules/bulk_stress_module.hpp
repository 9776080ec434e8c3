// The bulk stress of a suspension as a module of the time step (thesis eq. 4.1):
// the stress averaged over a cube centred in the cell, with the interfacial
// tension's contribution of the objects counted in it, and the effective shear
// rate of eq. 4.6 averaged the same way; bulk_stress.csv and summary.json.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "softflow/analysis/box_clipping.hpp"
#include "softflow/fem/field.hpp"
#include "softflow/io/report_table.hpp"
#include "softflow/simulation/step_module.hpp"

namespace softflow::simulation {

/// The bulk quantities of one time, over the cube V (eq. 4.1):
///   <sigma> = 1/V [ int_{V_m} sigma_m dV + sum_i int_{V_i} sigma_i dV
///                   - sum_i Gamma_i int_{S_i} (n n - I/3) dA ]
/// (plus, for interfaces with Navier slip, eta_m/V sum_i int_S [(u_d - u_m) n
/// + n (u_d - u_m)] dA), with V_m the matrix inside the cube and the sum over the objects whose
/// centre of volume lies in it (each counted whole, inside the cube or not;
/// an object whose centre lies outside is left out whole), sigma = -p I +
/// 2 eta D. The effective shear rate is the same average of 2 D_xy (signed:
/// eq. 4.6's sqrt(2 D:D) cannot oscillate; SPEC §9).
struct BulkStress {
  Eigen::Matrix3d stress = Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  /// The tension term alone (its xy component is the drops' elastic part).
  Eigen::Matrix3d tension = Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  /// The slip term alone, eta_m/V sum_i int_S [(u_d - u_m) n + n (u_d - u_m)] dA
  /// (0 without slip).
  Eigen::Matrix3d slip = Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  double shear_rate = std::numeric_limits<double>::quiet_NaN();  ///< <2 D_xy>
  /// V (<sigma>_xy - eta_m <2 D_xy>): the counted objects' stresslets S_xy
  /// summed (Batchelor 1970: int_V sigma = -int_V p I + 2 eta_m int_V D +
  /// sum S for a Newtonian matrix). Unlike <sigma>_xy / <2 D_xy>, it does
  /// not depend on the cube for objects wholly inside it.
  double stresslet_xy = std::numeric_limits<double>::quiet_NaN();
  double volume_fraction = 0.0;  ///< counted objects' volume / V
  int objects_counted = 0;
  double box_volume = 0.0;
};

/// One step's bulk quantities the moduli are fitted to (thesis eqs. 4.6-4.7).
struct BulkStressSample {
  double t, stress_xy, shear_rate, stresslet_xy, counted_volume;
};

/// G', G'' from the last `periods` periods of oscillatory flow
/// (analysis::fit_harmonic of <sigma>_xy and <2 D_xy> at the flow's
/// frequency): summary.json's "moduli", with the fit's residuals, the mean
/// volume fraction, the counted drops' stresslet against the wall shear rate
/// (S_xy = c eta_m V_d gamma_dot_w: c the intrinsic complex viscosity), and
/// Oldroyd's predictions beside them (appendix A) when the objects are drops.
/// A note instead when fewer periods have been run.
nlohmann::json oscillatory_moduli(std::span<const BulkStressSample> history, const io::CaseConfig& config,
                                  double box_volume);

/// What one row of bulk_stress.csv is made from.
struct BulkStressRow {
  const StepReport& report;
  const BulkStress& bulk;
};

/// bulk_stress.csv: one row per step.
const io::ReportTable<BulkStressRow>& bulk_stress_table();

/// In runs with bulk_stress.box_side > 0 (Newtonian phases without slip:
/// io::parse_case refuses the rest). Stage measure: BulkStress of the last
/// Stokes solution on the mesh it was solved on (NaN before the first solve).
/// The matrix's elements are clipped to the cube (analysis::clip_to_box on
/// their straight-sided vertices; exact for straight elements, the curved
/// ones at interfaces met only where an object straddles a face).
class BulkStressModule final : public StepModule {
 public:
  explicit BulkStressModule(const ModuleSetup& setup);
  [[nodiscard]] static bool wanted(const ModuleSetup& setup);

  [[nodiscard]] std::string name() const override { return "bulk_stress"; }
  void measure(const StepContext& context, StepReport& report) override;
  [[nodiscard]] std::vector<ReportFile> report_files() const override;
  void summarise(nlohmann::json& summary) const override;
  /// The history of the moduli's samples is checkpointed and carried over a remesh.
  [[nodiscard]] std::vector<StatePart> state_parts() override;
  void carry_over(StepModule& old, const fem::MeshTransfer& transfer) override;

  [[nodiscard]] const BulkStress& last() const { return last_; }

 private:
  /// The volume integrals of sigma and 2 D_xy over this rank's elements:
  /// region 0 clipped to the cube, the counted objects' regions whole.
  void integrate_volume(const std::vector<bool>& counted, Eigen::Matrix3d& stress,
                        double& shear_rate, double& volume) const;

  const mesh::Mesh& mesh_;
  const physics::StokesSystem& stokes_;
  analysis::Box box_;
  std::vector<double> viscosities_;  // per region, 0 = the matrix
  std::vector<double> tensions_;     // Gamma per object
  std::vector<bool> slips_;          // whether each object's interface slips
  fem::Field velocity_, pressure_;
  BulkStress last_;
  const io::CaseConfig& config_;
  std::vector<BulkStressSample> history_;  // one per time measured, ascending t
};

}  // namespace softflow::simulation
