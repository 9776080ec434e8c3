#include "softflow/physics/ale/mesh_velocity.hpp"

#include "softflow/common/error.hpp"
#include "softflow/time/bdf.hpp"

namespace softflow::physics {

std::vector<mesh::Point> bdf_mesh_velocity(const std::vector<mesh::Point>& x_new,
                                           const std::vector<mesh::Point>& x,
                                           const std::vector<mesh::Point>& x_old, double dt,
                                           double dt_previous) {
  if (x.size() != x_new.size() || (!x_old.empty() && x_old.size() != x_new.size()))
    throw Error("bdf_mesh_velocity: the position levels have different node counts");
  // No older level means the first step: BDF1 (the order the interface uses then).
  const auto c = time::bdf(x_old.empty() ? 1 : 2, dt, dt_previous);
  std::vector<mesh::Point> u(x_new.size());
  for (std::size_t i = 0; i < u.size(); ++i)
    u[i] = x_old.empty() ? mesh::Point((c.a0 * x_new[i] + c.a1 * x[i]) / dt)
                         : mesh::Point((c.a0 * x_new[i] + c.a1 * x[i] + c.a2 * x_old[i]) / dt);
  return u;
}

}  // namespace softflow::physics
