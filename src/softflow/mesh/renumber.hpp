// Node renumbering for locality.
#pragma once

#include <vector>

#include "softflow/mesh/mesh.hpp"

namespace softflow::mesh {

/// Renumbers the nodes along a Morton (Z-order) curve of their positions, so
/// that vertices and edge nodes close in space are close in number. gmsh
/// numbers every vertex before every edge node; contiguous node ranges (one
/// per MPI rank, see fem::DofMap) are then spatially scattered, and one
/// rank ends up owning the first node of every element. After renumbering,
/// contiguous ranges are compact subdomains and element loops touch memory
/// in order. Periodic representatives stay the smallest index of their class.
/// Returns each old node's new index (for callers that carry node data over).
std::vector<int> renumber_nodes_spatially(Mesh& mesh);

}  // namespace softflow::mesh
