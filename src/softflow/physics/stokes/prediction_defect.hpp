// The defect of the Stokes step's predicted conformation, carried to the
// next step (docs/viscoelastic.md, "The predicted stress and the
// transported one").
//
// The Stokes step balances momentum with the polymer stress at the
// D'Avino-Hulsen prediction c_p(u), formed point by point at the quadrature
// points (viscoelastic_terms.hpp). The run then keeps the conformation the
// transport computes from the same velocity: a P1 field, the SUPG-Galerkin
// projection of the same equation (physics::AleTransport on log c). Where
// the flow is not homogeneous the two differ at a point by
//
//   d = c_{n+1} - c_p(u_{n+1}) ~ theta dt (Pi F - F),
//
// F the conformation's rate (it holds grad u, discontinuous between P2
// elements) and Pi the projection: the momentum balance held for a stress
// the run never stores, and the velocity is off by G d / eta, first order in
// dt (measured: the drop in a Giesekus matrix of docs/viscoelastic.md). d
// changes by O(dt^2) from a step to the next, so the next step adds the last
// d, scaled by the ratio of the steps' theta dt, to its prediction: the
// stress it balances is then the one the transport will keep, to O(dt^2).
//
// d is measured on every tetrahedron this rank's Stokes assembly visits
// (fem::elements_touching its node range) in a phase with a conformation,
// at the points of the Stokes rule. It is dropped (the next step takes the
// Euler prediction alone) after a remesh, whose points are new, and after a
// jump of the flow, where it is not smooth in time.
#pragma once

#include <string>
#include <vector>

#include "softflow/physics/stokes/point_tensors.hpp"
#include "softflow/physics/stokes/stokes_problem.hpp"

namespace softflow {
class StateRecord;
}  // namespace softflow

namespace softflow::mesh {
struct Mesh;
}  // namespace softflow::mesh

namespace softflow::physics {

class PredictionDefect {
 public:
  /// `has_conformation[r]`: region r carries a conformation tensor.
  PredictionDefect(const mesh::Mesh& mesh, const std::vector<bool>& has_conformation);

  /// After the Stokes solve, before the transport: the prediction at the
  /// solved `velocity`, from `coupling` as the solve had it but without the
  /// defect it added (d is the whole difference, which the next step adds
  /// again; c_{n+1} minus the prediction with d would be only its change).
  void record_prediction(const ViscoelasticCoupling& coupling, const fem::Field& velocity);
  /// After the transport: d = c_{n+1} - the recorded prediction, at every point.
  void measure(const fem::Field& conformation);
  /// Gives `coupling` (set up for its step: bdf and dt) the last d; nothing
  /// before a first measure() or after reset().
  void apply(ViscoelasticCoupling& coupling) const;
  /// The next step takes no d.
  void reset() { measured_ = false; }
  [[nodiscard]] bool measured() const { return measured_; }

  /// As part of a run's state (a checkpoint: every point of the mesh, so
  /// that a restart on any number of ranks continues alike; a rank's own
  /// step record: its points).
  void save(StateRecord& record, const std::string& prefix) const;
  void restore(const StateRecord& record, const std::string& prefix);

 private:
  const mesh::Mesh& mesh_;
  PointTensors values_;  // the prediction between record and measure, d after
  bool measured_ = false;
  double theta_dt_ = 0.0;  // of the step d was measured at
};

}  // namespace softflow::physics
