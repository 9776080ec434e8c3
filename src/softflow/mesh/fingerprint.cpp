#include "softflow/mesh/fingerprint.hpp"

#include "softflow/common/fnv1a.hpp"

namespace softflow::mesh {

std::uint64_t fingerprint(const Mesh& mesh) {
  Fnv1a h;
  for (const auto& x : mesh.nodes) {
    const double xyz[3] = {x.x(), x.y(), x.z()};
    h.scalar(xyz);
  }
  h.array(mesh.tets);
  h.array(mesh.tet_region);
  h.array(mesh.boundary_faces);
  h.array(mesh.interface_faces);
  h.array(mesh.interface_object);
  h.array(mesh.periodic_master);
  return h.value();
}

}  // namespace softflow::mesh
