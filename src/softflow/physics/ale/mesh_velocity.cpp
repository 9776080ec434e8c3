#include "softflow/physics/ale/mesh_velocity.hpp"

#include "softflow/common/error.hpp"

namespace softflow::physics {

std::vector<mesh::Point> bdf_mesh_velocity(const std::vector<mesh::Point>& x_new,
                                           const std::vector<mesh::Point>& x,
                                           const std::vector<mesh::Point>& x_old, double dt) {
  if (x.size() != x_new.size() || (!x_old.empty() && x_old.size() != x_new.size()))
    throw Error("bdf_mesh_velocity: the position levels have different node counts");
  std::vector<mesh::Point> u(x_new.size());
  for (std::size_t i = 0; i < u.size(); ++i)
    u[i] = x_old.empty() ? mesh::Point((x_new[i] - x[i]) / dt)
                         : mesh::Point((3.0 * x_new[i] - 4.0 * x[i] + x_old[i]) / (2.0 * dt));
  return u;
}

}  // namespace softflow::physics
