// The viscoelastic phases of a run (thesis §2.3.1-2.3.2, SPEC §2 parts 4-5):
// the conformation fields, their transport, and what the Stokes step needs.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "softflow/common/state.hpp"
#include "softflow/fem/field.hpp"
#include "softflow/mesh/mesh.hpp"
#include "softflow/physics/stokes/prediction_defect.hpp"
#include "softflow/physics/stokes/stokes_problem.hpp"
#include "softflow/physics/transport/ale_transport.hpp"
#include "softflow/physics/viscoelastic/conformation_prediction.hpp"
#include "softflow/physics/viscoelastic/constitutive.hpp"

namespace softflow::fem {
class MeshTransfer;
}  // namespace softflow::fem

namespace softflow::simulation {

/// The volume average of a phase's polymer (or elastic) stress tau = G (c - I)
/// over one region (thesis Fig. 2.15), and how uniform it is.
struct RegionStress {
  int region = 0;
  double volume = 0.0;
  Eigen::Matrix3d mean = Eigen::Matrix3d::Zero();  ///< <tau>
  Eigen::Vector3d principal = Eigen::Vector3d::Zero();  ///< eigenvalues of <tau>, descending
  /// sqrt(<|tau - <tau>|^2>) / |<tau>| (Frobenius norms): 0 for a uniform stress.
  double spread = 0.0;
  /// <tau_xx> - <tau_yy>: the first normal stress difference's contribution.
  [[nodiscard]] double first_normal_stress_difference() const { return mean(0, 0) - mean(1, 1); }
};

/// Everything a run keeps for its phases with a conformation tensor, on the
/// moving mesh:
///   log_conformation  s = log c: 6 x P1 per region (xx, yy, zz, xy, yz, xz),
///                     discontinuous at interfaces; zero (c = I) at t = 0;
///   conformation      c = exp(s) node by node (eq. 2.42 lumped: the nodal
///                     interpolant of exp(s_h), which keeps c positive definite);
///   polymer_stress    tau(c): G (c - I) (eqs. 2.6, 2.22), G (f c - I) for FENE-P;
/// and, internally, the velocity and mesh velocity as fields and the
/// projected velocity gradient G_n (DEVSS-G).
///
/// One step: coupling() gives the Stokes step the D'Avino-Hulsen/DEVSS-G
/// data for t_{n+1} (c_n, with the consistent prediction also c_{n-1}, the
/// transport's BDF step and the last defect; u_m, G_n); after the Stokes
/// solve, advance() transports s to t_{n+1} with u_{n+1} (physics::AleTransport,
/// SUPG, BDF1 then BDF2, source log_conformation_source), updates c,
/// tau and G, and measures the prediction's defect (physics::PredictionDefect).
/// Newtonian regions carry zeros throughout.
class ViscoelasticPhases {
 public:
  /// `models[r]` for region r (0 = matrix, k = object k); the mesh is the
  /// run's and must outlive this object.
  /// `slip_velocity`: the Stokes velocity has a copy per region (interface
  /// slip), and the transport reads each region's own copy.
  /// `supg_taus[r]`: the transport's SUPG parameter in region r
  /// (physics::AleTransport; steady where not given).
  /// `prediction`: the conformation the Stokes step's stress is taken at
  /// (physics::viscoelastic::StressPrediction).
  ViscoelasticPhases(const mesh::Mesh& mesh,
                     std::vector<physics::viscoelastic::Constitutive> models,
                     bool slip_velocity = false, std::vector<physics::SupgTau> supg_taus = {},
                     physics::viscoelastic::StressPrediction prediction =
                         physics::viscoelastic::StressPrediction::consistent,
                     bool devss_g = true);
  ~ViscoelasticPhases();
  ViscoelasticPhases(const ViscoelasticPhases&) = delete;
  ViscoelasticPhases& operator=(const ViscoelasticPhases&) = delete;

  /// True if some region has a conformation tensor.
  [[nodiscard]] static bool needed(const std::vector<physics::viscoelastic::Constitutive>& models);

  /// The Stokes step's viscoelastic data for the step to t_{n+1}: u_m is the
  /// mesh velocity over that step at every geometry node. The result points
  /// to fields of this object. Collective.
  [[nodiscard]] physics::ViscoelasticCoupling coupling(std::span<const mesh::Point> mesh_velocity,
                                                       double dt);
  /// After the Stokes solve of step `step` to time t_new: transports s with
  /// the new velocity (`solution`, distributed over `stokes_dofs`) and updates c, tau
  /// and G. Throws SolverError naming the step, time, region, node and
  /// position if s is not finite. Collective.
  void advance(const fem::DofMap& stokes_dofs, Vec solution, double dt,
               double t_new, int step);

  /// After a jump of the flow at t_n (physics::WallMotion::jumps_at): the
  /// next step starts the BDF and DEVSS-G histories afresh (BDF1, no G).
  void restart_time_history();

  /// After a remesh: s, c, tau, the DEVSS-G gradient G_n and the
  /// transport's history s_{n-1} from `old` (the phases on the old mesh)
  /// through `transfer`: BDF2 and DEVSS-G go on across the remesh.
  /// Collective.
  void carry_over(ViscoelasticPhases& old, const fem::MeshTransfer& transfer);

  /// <tau> over region r on the current mesh. Collective.
  [[nodiscard]] RegionStress region_stress(int region) const;

  [[nodiscard]] const std::vector<physics::viscoelastic::Constitutive>& models() const {
    return models_;
  }
  /// The fields a run writes and checkpoints (log_conformation, conformation, polymer_stress).
  [[nodiscard]] std::vector<fem::Field*> output_fields();
  /// What a checkpoint needs besides those fields: the transport's BDF
  /// history and the projected gradients ("viscoelastic").
  [[nodiscard]] StatePart state_part();

 private:
  /// Throws SolverError (step, time, node, region, position, what to try)
  /// if s has a non-finite value anywhere. Collective.
  void check_finite(double t_new, int step);
  /// "node N in the matrix (in object k), near (x, y, z)": where a dof of s is.
  [[nodiscard]] std::string place(int dof) const;
  /// c = exp(s), tau = tau(c) node by node; throws SolverError (step, time,
  /// node, region, position, the model's reason) where the model does not
  /// admit c (FENE-P: tr c >= L^2). Collective.
  void update_conformation_and_stress(double t_new, int step);
  void update_velocity_gradient();
  /// previous_conformation_ = exp(s_{n-1}) at every node.
  void update_previous_conformation();
  /// c = exp(s) node by node (I in Newtonian regions), ghosts updated.
  void exponentiate(const fem::Field& s, fem::Field& c) const;
  /// After carry_over(): the prediction's defect on this mesh, from a dry
  /// repetition of the last step (PredictionDefect). Collective.
  void estimate_defect(const ViscoelasticPhases& old, const fem::MeshTransfer& transfer);

  const mesh::Mesh& mesh_;
  std::vector<physics::viscoelastic::Constitutive> models_;
  std::shared_ptr<const fem::Space> p1_, p2_, velocity_space_;
  fem::Field log_conformation_, conformation_, stress_;
  fem::Field previous_conformation_;  // exp(s_{n-1}) at the nodes, for the BDF2 prediction
  fem::Field velocity_, mesh_velocity_;
  fem::Field gradient_;
  std::vector<physics::SupgTau> supg_taus_;
  bool devss_g_ = true;
  std::unique_ptr<physics::AleTransport> transport_;
  physics::AleTransport::Source source_;
  int gradient_steps_ = 0;  // projections of G done so far
  physics::viscoelastic::StressPrediction prediction_ =
      physics::viscoelastic::StressPrediction::consistent;
  physics::ViscoelasticCoupling last_coupling_;      // the Stokes step's, for the defect
  std::optional<physics::PredictionDefect> defect_;  // with the consistent prediction
};

}  // namespace softflow::simulation
