// Replicates a mesh built on rank 0 to every rank.
#pragma once

#include <mpi.h>

#include "softflow/mesh/mesh.hpp"

namespace softflow::parallel {

/// After the call every rank holds rank 0's mesh. Meshing runs on one rank
/// only (gmsh is serial), and the mesh is small next to the matrices.
void broadcast_mesh(mesh::Mesh& mesh, MPI_Comm comm);

}  // namespace softflow::parallel
