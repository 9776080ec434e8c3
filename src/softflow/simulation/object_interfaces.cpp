#include "softflow/simulation/object_interfaces.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>

#include <fmt/format.h>

#include "softflow/analysis/ellipsoid_fit.hpp"
#include "softflow/common/error.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/simulation/case_flow.hpp"
#include "softflow/time/bdf.hpp"

namespace softflow::simulation {

using physics::Vec3;

ObjectInterfaces::ObjectInterfaces(const io::CaseConfig& config, const mesh::Mesh& mesh) : config_(config) {
  physics::InterfaceTrackerSettings tracking;
  tracking.redistribution_factor = redistribution_rate(config_);
  tracking.supg_beta = config_.interface.supg_beta;
  for (int k = 1; k <= mesh.n_objects; ++k) {
    auto surface = physics::extract_interface(mesh, k);
    auto x0 = physics::interface_positions(surface, mesh);
    trackers_.emplace_back(std::move(surface), std::move(x0), tracking);
  }
  last_centre_velocity_.assign(trackers_.size(), Vec3::Zero());
  for (const auto& tracker : trackers_)
    initial_volumes_.push_back(physics::surface_integrals(tracker.surface(), tracker.positions()).volume);
}

InterfacePositions ObjectInterfaces::predict(double dt) const {
  InterfacePositions x_hat;
  for (const auto& tracker : trackers_) x_hat.push_back(tracker.predict(dt));
  return x_hat;
}

std::vector<Vec3> ObjectInterfaces::advance_centres(const InterfacePositions& x_hat, double dt, double& x_shift) {
  // U from the centre of volume of the predicted surface (eqs. 2.51-2.54);
  // with one object, the mesh follows its centre in x so the drop never
  // drifts towards the periodic faces (d1 of Step 2).
  std::vector<Vec3> u(trackers_.size());
  x_shift = 0.0;
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const Vec3 before = trackers_[k].centre();
    u[k] = trackers_[k].centre_velocity(x_hat[k], dt);
    if (trackers_.size() == 1) x_shift = trackers_[k].centre().x() - before.x();
  }
  return u;
}

std::vector<physics::InterfacePlacement> ObjectInterfaces::placements(const InterfacePositions& x_hat) const {
  std::vector<physics::InterfacePlacement> placed;
  for (std::size_t k = 0; k < trackers_.size(); ++k)
    placed.push_back({trackers_[k].surface().volume_node, x_hat[k]});
  return placed;
}

physics::SemiImplicitTension ObjectInterfaces::semi_implicit_tension(const InterfacePositions& x_hat, double dt,
                                                                     int n_mesh_nodes,
                                                                     const InterfaceVelocity& velocity) const {
  physics::SemiImplicitTension tension;
  if (!config_.interface.semi_implicit_tension || trackers_.empty()) return tension;
  // theta = 1 for the BDF1 first step, 2/3 after (eqs. 2.48, 2.50). w = the
  // previous step's fluid velocity along the normal: the implicit part then
  // acts on the velocity increment only (see physics::SemiImplicitTension).
  // At the first step there is no previous velocity; w = 0 is exact there,
  // since the BDF1 predictor does not move the interface.
  const int order = time::bdf_order(trackers_.front().steps());
  const bool first_step = order == 1;
  tension.theta_dt = time::bdf(order, dt, trackers_.front().last_step()).theta_dt(dt);
  tension.node_normal.assign(n_mesh_nodes, Vec3::Zero());
  tension.predicted_normal_velocity.assign(n_mesh_nodes, 0.0);
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const auto& tracker = trackers_[k];
    const auto normals = physics::node_normals(tracker.surface(), x_hat[k]);
    const auto& nodes = tracker.surface().volume_node;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      tension.node_normal[nodes[i]] = normals[i];
      if (!first_step)
        tension.predicted_normal_velocity[nodes[i]] = normals[i].dot(velocity(nodes[i], static_cast<int>(k) + 1));
    }
  }
  return tension;
}

void ObjectInterfaces::correct(const InterfacePositions& x_hat, const std::vector<Vec3>& centre_velocity, double dt,
                               const InterfaceVelocity& velocity) {
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const auto& nodes = trackers_[k].surface().volume_node;
    std::vector<Vec3> u(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) u[i] = velocity(nodes[i], static_cast<int>(k) + 1);
    trackers_[k].correct(x_hat[k], u, centre_velocity[k], dt);
  }
}

bool ObjectInterfaces::extrapolating() const { return !trackers_.empty() && trackers_.front().steps() > 0; }

double ObjectInterfaces::interface_change(const InterfacePositions& x_hat) const {
  // The predictor's error, dt^2 x'' (1 + w) / 2 to leading order: the
  // scheme's geometric error, since Stokes was solved on x_hat. The whole
  // distance, tangential part included: measured on the main example, the
  // normal part alone let a step of 1.8 / gamma_dot through, after which D
  // kept a two-step oscillation of +-1e-4 that never settled; the
  // tangential motion of the redistribution (eq. 2.30) is where such a step
  // shows first.
  double change = 0.0;
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const double radius = std::cbrt(3.0 * initial_volumes_[k] / (4.0 * std::numbers::pi));
    const auto& x = trackers_[k].positions();
    for (std::size_t i = 0; i < x.size(); ++i) change = std::max(change, (x[i] - x_hat[k][i]).norm() / radius);
  }
  return change;
}

void ObjectInterfaces::restart_histories() {
  for (auto& tracker : trackers_) tracker.restart_history();
}

ObjectState ObjectInterfaces::measure(int k, const Vec3& centre_velocity) const {
  const auto& tracker = trackers_[k];
  const auto& x = tracker.positions();
  const auto integrals = physics::surface_integrals(tracker.surface(), x);
  ObjectState s;
  s.object = k + 1;
  s.volume = integrals.volume;
  s.area = integrals.area;
  s.centre = integrals.centre_of_volume();
  s.centre_velocity = centre_velocity;
  const auto fit = analysis::fit_ellipsoid(x);
  s.deformation = fit.deformation;
  // An undeformed sphere has no long axis: its fitted angle is whatever the
  // round-off picks (0 or 90 deg at t = 0), which would distort averages
  // and plots. NaN says "undefined" ("nan" in CSV, null in JSON).
  s.theta_deg = fit.deformation < kOrientationUndefinedBelow ? std::numeric_limits<double>::quiet_NaN()
                                                             : fit.theta_deg;
  s.L = fit.L;
  s.B = fit.B;
  s.W = fit.W;
  s.ellipsoid_deviation = fit.max_relative_deviation;
  return s;
}

void ObjectInterfaces::set_initial_volumes(std::vector<double> volumes) {
  if (volumes.size() != initial_volumes_.size())
    throw InputError("the checkpoint's initial volumes do not fit the mesh it carries");
  initial_volumes_ = std::move(volumes);
}

void ObjectInterfaces::check_volumes(int step, double time) const {
  // The discrete scheme conserves volume only approximately (thesis §2.4);
  // past a few per cent the drop is no longer the one asked for, and D and
  // theta of a drop of another size compare with the wrong theory.
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const double volume = physics::surface_integrals(trackers_[k].surface(), trackers_[k].positions()).volume;
    const double drift = volume / initial_volumes_[k] - 1.0;
    if (std::abs(drift) <= config_.time.max_volume_drift) continue;
    const Vec3 c = trackers_[k].centre();
    throw AccuracyError(fmt::format(
        "step {} (t = {:.4f}): object {} (centre ({:.3f}, {:.3f}, {:.3f})) changed its volume by "
        "{:+.3g} % (from {:.6g} to {:.6g}), more than time.max_volume_drift = {:g} %. Try a "
        "smaller time.step, more mesh.equator_nodes, or a larger time.max_volume_drift if this "
        "accuracy is enough",
        step, time, k + 1, c.x(), c.y(), c.z(), 100.0 * drift, initial_volumes_[k], volume,
        100.0 * config_.time.max_volume_drift));
  }
}

std::vector<StatePart> ObjectInterfaces::state_parts() {
  std::vector<StatePart> parts;
  for (std::size_t k = 0; k < trackers_.size(); ++k)
    parts.push_back({fmt::format("objects/{}", k + 1),
                     [this, k](StateRecord& r, const std::string& p) {
                       const auto h = trackers_[k].history();
                       r.set(p + "x", h.x);
                       r.set(p + "x_previous", h.x_previous);
                       r.set(p + "centre", std::vector<Vec3>{h.centre, h.centre_previous});
                       r.set(p + "steps", h.steps);
                       r.set(p + "centre_steps", h.centre_steps);
                       r.set(p + "last_step", h.last_step);
                       r.set(p + "last_centre_velocity", std::vector<Vec3>{last_centre_velocity_[k]});
                       // After a remesh the reference mesh's interface is not the initial one.
                       r.set(p + "reference_areas", trackers_[k].reference_areas());
                     },
                     [this, k](const StateRecord& r, const std::string& p) {
                       const auto centre = r.get_points(p + "centre");
                       const auto velocity = r.get_points(p + "last_centre_velocity");
                       auto x = r.get_points(p + "x");
                       auto x_previous = r.get_points(p + "x_previous");
                       if (centre.size() != 2 || velocity.size() != 1 ||
                           x.size() != trackers_[k].positions().size() || x_previous.size() != x.size())
                         throw InputError(
                             fmt::format("the saved state of object {} does not fit its interface mesh", k + 1));
                       const int steps = r.get_int(p + "steps");
                       // Checkpoints from before variable steps: every step was time.step.
                       const double last_step = r.contains(p + "last_step")
                                                    ? r.get_double(p + "last_step")
                                                    : (steps > 0 ? config_.time.step : 0.0);
                       trackers_[k].restore({std::move(x), std::move(x_previous), centre[0], centre[1], steps,
                                             r.get_int(p + "centre_steps"), last_step});
                       last_centre_velocity_[k] = velocity[0];
                       if (r.contains(p + "reference_areas"))  // records from before remeshing: the initial ones
                         trackers_[k].set_reference_areas(r.get_array(p + "reference_areas"));
                     }});
  return parts;
}

double ObjectInterfaces::carry_over(
    const ObjectInterfaces& old, std::span<const int> new_node_of_old,
    std::span<const char> resampled,
    std::span<const geometry::InterfaceSurface::Origin> old_surface_point) {
  if (old.trackers_.size() != trackers_.size() || resampled.size() != trackers_.size())
    throw Error("remesh: the number of objects changed");
  last_centre_velocity_ = old.last_centre_velocity_;
  initial_volumes_ = old.initial_volumes_;
  double volume_change = 0.0;
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const auto& before = old.trackers_[k];
    const double volume_before =
        physics::surface_integrals(before.surface(), before.positions()).volume;
    if (resampled[k]) {
      auto h = before.history();
      const auto& surface = trackers_[k].surface();
      std::map<int, int> old_local;  // old mesh node -> old tracker node
      for (int i = 0; i < before.surface().n_nodes(); ++i)
        old_local[before.surface().volume_node[i]] = i;
      // x_{n-1} = x_n less the last step's displacement x_n - x_{n-1},
      // interpolated on the old curved triangles: the new x_n carries the
      // offset that restored the volume, and so does x_{n-1}, so that the
      // two levels' volumes differ as the old ones did (interpolating x_{n-1}
      // itself gave it the resampling's own volume error, which BDF2 turned
      // into a jump of 1e-3 in the particle's volume at the next step).
      const std::vector<Vec3> old_x = h.x;
      h.x = trackers_[k].positions();
      if (!h.x_previous.empty()) {
        std::vector<Vec3> previous(surface.n_nodes());
        for (int i = 0; i < surface.n_nodes(); ++i) {
          const auto& at = old_surface_point[surface.volume_node[i]];
          if (at.triangle < 0)
            throw Error("remesh: a resampled interface node has no place on the old interface");
          const auto n = element::p2_triangle_values(Vec3(at.xi.x(), at.xi.y(), 0.0));
          Vec3 displacement = Vec3::Zero();
          for (int c = 0; c < 6; ++c) {
            const int j = old_local.at(at.mesh_nodes[c]);
            displacement += n[c] * (old_x[j] - h.x_previous[j]);
          }
          previous[i] = h.x[i] - displacement;
        }
        h.x_previous = std::move(previous);
      }
      trackers_[k].restore(std::move(h));
      const double volume_after =
          physics::surface_integrals(trackers_[k].surface(), trackers_[k].positions()).volume;
      volume_change = std::max(volume_change, std::abs(volume_after / volume_before - 1.0));
      continue;
    }
    const auto& old_nodes = before.surface().volume_node;
    const auto& surface = trackers_[k].surface();
    // The interface nodes are the old ones: the histories (x_n, x_{n-1},
    // the centres) carry over in the new surface's node order.
    const int n_mesh_nodes = surface.volume_node.empty()
                                 ? 0
                                 : *std::max_element(surface.volume_node.begin(), surface.volume_node.end()) + 1;
    std::vector<int> local(n_mesh_nodes, -1);
    for (int i = 0; i < surface.n_nodes(); ++i) local[surface.volume_node[i]] = i;
    const auto local_of_old = [&](int old_local) {
      return local.at(new_node_of_old[old_nodes.at(old_local)]);
    };
    auto h = before.history();
    auto remap = [&](const std::vector<Vec3>& x) {
      std::vector<Vec3> out(x.size());
      for (std::size_t i = 0; i < x.size(); ++i) out.at(local_of_old(static_cast<int>(i))) = x[i];
      return out;
    };
    h.x = remap(h.x);
    if (!h.x_previous.empty()) h.x_previous = remap(h.x_previous);
    trackers_[k].restore(std::move(h));
    // The redistribution keeps the run's initial element areas (eq. 2.32's
    // reference), triangle by triangle: the triangles are the old ones.
    auto key = [](std::array<int, 3> t) {
      std::sort(t.begin(), t.end());
      return t;
    };
    std::map<std::array<int, 3>, int> new_triangle;
    for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
      const auto& tri = surface.triangles[t];
      new_triangle[key({tri[0], tri[1], tri[2]})] = static_cast<int>(t);
    }
    const auto& old_triangles = before.surface().triangles;
    const auto& old_areas = before.reference_areas();
    std::vector<double> areas(surface.triangles.size(), 0.0);
    for (std::size_t t = 0; t < old_triangles.size(); ++t) {
      std::array<int, 3> corners{};
      for (int c = 0; c < 3; ++c) corners[c] = local_of_old(old_triangles[t][c]);
      areas.at(new_triangle.at(key(corners))) = old_areas[t];
    }
    trackers_[k].set_reference_areas(std::move(areas));
    const double volume_after = physics::surface_integrals(surface, trackers_[k].positions()).volume;
    volume_change = std::max(volume_change, std::abs(volume_after / volume_before - 1.0));
  }
  return volume_change;
}

}  // namespace softflow::simulation
