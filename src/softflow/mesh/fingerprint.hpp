// A 64-bit fingerprint of a mesh, to tell whether two meshes are the same to the bit.
#pragma once

#include <cstdint>

#include "softflow/mesh/mesh.hpp"

namespace softflow::mesh {

/// FNV-1a (64 bits) over the node coordinates' bytes, the elements, their
/// regions, the boundary and interface faces and the periodic masters: any
/// difference in any of them (one ulp of one coordinate included) changes it,
/// while equal meshes always give equal fingerprints.
[[nodiscard]] std::uint64_t fingerprint(const Mesh& mesh);

}  // namespace softflow::mesh
