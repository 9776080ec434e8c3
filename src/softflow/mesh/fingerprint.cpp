#include "softflow/mesh/fingerprint.hpp"

#include <cstring>
#include <span>

namespace softflow::mesh {

namespace {

class Fnv1a {
 public:
  void add(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) {
      hash_ ^= p[i];
      hash_ *= 0x100000001b3ULL;
    }
  }
  template <class T>
  void add_all(const std::vector<T>& values) {
    const std::uint64_t n = values.size();
    add(&n, sizeof n);  // lengths too: [a][bc] and [ab][c] differ
    if (!values.empty()) add(values.data(), values.size() * sizeof(T));
  }
  [[nodiscard]] std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

}  // namespace

std::uint64_t fingerprint(const Mesh& mesh) {
  Fnv1a h;
  for (const auto& x : mesh.nodes) {
    const double xyz[3] = {x.x(), x.y(), x.z()};
    h.add(xyz, sizeof xyz);
  }
  h.add_all(mesh.tets);
  h.add_all(mesh.tet_region);
  h.add_all(mesh.boundary_faces);
  h.add_all(mesh.interface_faces);
  h.add_all(mesh.interface_object);
  h.add_all(mesh.periodic_master);
  return h.value();
}

}  // namespace softflow::mesh
