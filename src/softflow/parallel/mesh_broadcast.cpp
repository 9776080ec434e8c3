#include "softflow/parallel/mesh_broadcast.hpp"

#include <cstring>
#include <type_traits>
#include <vector>

namespace softflow::parallel {

namespace {

// Broadcasts a vector of trivially copyable elements as bytes.
template <class T>
void broadcast_vector(std::vector<T>& v, MPI_Comm comm, int rank) {
  static_assert(std::is_trivially_copyable_v<T>);
  long n = static_cast<long>(v.size());
  MPI_Bcast(&n, 1, MPI_LONG, 0, comm);
  if (rank != 0) v.resize(n);
  if (n > 0) MPI_Bcast(static_cast<void*>(v.data()), static_cast<int>(n * sizeof(T)), MPI_BYTE, 0, comm);
}

}  // namespace

void broadcast_mesh(mesh::Mesh& mesh, MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  MPI_Bcast(&mesh.box, sizeof(mesh::Box), MPI_BYTE, 0, comm);
  MPI_Bcast(&mesh.n_objects, 1, MPI_INT, 0, comm);
  std::vector<double> xyz;
  if (rank == 0)
    for (const auto& p : mesh.nodes) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  broadcast_vector(xyz, comm, rank);
  if (rank != 0) {
    mesh.nodes.resize(xyz.size() / 3);
    for (std::size_t i = 0; i < mesh.nodes.size(); ++i)
      mesh.nodes[i] = mesh::Point(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  }
  broadcast_vector(mesh.is_vertex, comm, rank);
  broadcast_vector(mesh.tets, comm, rank);
  broadcast_vector(mesh.tet_region, comm, rank);
  broadcast_vector(mesh.boundary_faces, comm, rank);
  broadcast_vector(mesh.boundary_face_tag, comm, rank);
  broadcast_vector(mesh.interface_faces, comm, rank);
  broadcast_vector(mesh.interface_object, comm, rank);
  broadcast_vector(mesh.periodic_master, comm, rank);
}

}  // namespace softflow::parallel
