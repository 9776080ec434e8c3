#include "support/verification/extensional_flow.hpp"

#include <cmath>

#include "softflow/geometry/shear_cell.hpp"
#include "softflow/physics/interface/interface_tracker.hpp"

namespace softflow::verification {

TrackingErrors track_sphere_in_extension(int equator_nodes, double dt, double k,
                                         double step_variation) {
  geometry::ShearCellSpec spec;
  spec.box.length = spec.box.height = spec.box.width = 6.0;
  spec.objects.push_back(geometry::ObjectSpec{});
  spec.sizing.equator_nodes = equator_nodes;
  spec.sizing.far_size = 2.0;
  const auto mesh = geometry::build_shear_cell(spec);
  auto surface = physics::extract_interface(mesh, 1);
  auto x0 = physics::interface_positions(surface, mesh);
  physics::InterfaceTrackerSettings settings;
  settings.redistribution_factor = k;
  physics::InterfaceTracker tracker(std::move(surface), std::move(x0), settings);

  const double t_end = 0.5;
  const int n_steps = static_cast<int>(std::lround(t_end / dt));
  auto velocity = [](const physics::Vec3& x) { return physics::Vec3(x.x(), -x.y() / 2, -x.z() / 2); };
  double t = 0.0;
  for (int step = 0; step < n_steps; ++step) {
    // With an odd count the last step is dt: the run still ends at t_end.
    const bool last_unpaired = n_steps % 2 == 1 && step == n_steps - 1;
    const double h = last_unpaired ? dt : dt * (1.0 + (step % 2 == 0 ? step_variation : -step_variation));
    const auto x_hat = tracker.predict(h);
    std::vector<physics::Vec3> u(x_hat.size());
    for (std::size_t i = 0; i < x_hat.size(); ++i) u[i] = velocity(x_hat[i]);  // the flow at t_{n+1}
    const auto u_centre = tracker.centre_velocity(x_hat, h);
    tracker.correct(x_hat, u, u_centre, h);
    t += h;
  }

  const physics::Vec3 semi_axes(std::exp(t), std::exp(-t / 2), std::exp(-t / 2));
  TrackingErrors e;
  e.equator_nodes = equator_nodes;
  e.interface_nodes = tracker.surface().n_nodes();
  e.dt = dt;
  double sum2 = 0.0;
  for (const auto& p : tracker.positions()) {
    const double s = 1.0 / p.cwiseQuotient(semi_axes).norm();  // s p lies on the spheroid
    const double error = std::abs(1.0 - s) * p.norm();
    e.e_max = std::max(e.e_max, error);
    sum2 += error * error;
  }
  e.e_2 = std::sqrt(sum2 / static_cast<double>(tracker.positions().size()));
  return e;
}

}  // namespace softflow::verification
