// Benchmark: one two-phase Stokes solve on the thesis's 'unbounded' shear cell.
//
//   stokes_solve [direct|iterative] [equator_nodes] [repeats]
//   mpirun -np 2 stokes_solve iterative 40
//
// Box 15 drop diameters (30 R) per side, periodic in x and z, a unit drop
// with lambda = 1 and Ca = 0.1 at the centre. Prints one JSON line per
// repeat: unknowns, mesh/assembly/solve seconds, iterations, and the error of
// the solution against the direct solve's reference quantities is left to
// the caller (bench/run_stokes_bench.py compares methods within one run).
#include <chrono>
#include <cstdio>
#include <string>

#include <fmt/format.h>
#include <petscsys.h>

#include "softflow/analysis/interface_measures.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/parallel/mesh_broadcast.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"

using namespace softflow;

int main(int argc, char** argv) {
  const std::string method = argc > 1 ? argv[1] : "direct";
  const int equator_nodes = argc > 2 ? std::stoi(argv[2]) : 40;
  const int repeats = argc > 3 ? std::stoi(argv[3]) : 1;
  int petsc_argc = 1;
  if (PetscInitialize(&petsc_argc, &argv, nullptr, nullptr) != 0) return 1;
  {
    const int rank = la::mpi_rank(), size = la::mpi_size();
    geometry::ShearCellSpec spec;
    spec.box.length = spec.box.height = spec.box.width = 30.0;
    spec.objects.push_back(geometry::ObjectSpec{});
    spec.sizing.equator_nodes = equator_nodes;
    mesh::Mesh mesh;
    geometry::MeshReport report;
    if (rank == 0) mesh = geometry::build_shear_cell(spec, &report);
    parallel::broadcast_mesh(mesh, PETSC_COMM_WORLD);

    la::SaddlePointSettings settings;
    settings.method = method == "direct" ? la::SaddlePointMethod::direct
                                         : la::SaddlePointMethod::iterative;
    physics::StokesProblem problem;
    problem.viscosity = {1.0, 1.0};
    problem.interfacial_tension = {10.0};  // Ca = 0.1 with gamma_dot = R = eta = 1
    problem.boundary_velocity = [](const Eigen::Vector3d& x) { return Eigen::Vector3d(x.y(), 0, 0); };
    problem.pressure_gauge_node = physics::default_pressure_gauge_node(mesh);
    // Each repeat builds a fresh system: a "cold" solve (matrix pattern,
    // factorisation or multigrid setup, solve), then a "warm" one of the same
    // problem (the direct method's GMRES reuses the factorisation, as in a
    // time loop whose mesh moves slowly).
    for (int r = 0; r < repeats; ++r) {
      physics::StokesSystem system(mesh, settings);
      for (const char* phase : {"cold", "warm"}) {
        const auto result = system.solve(problem);
        const auto m = analysis::object_measures(mesh, system.dofs(), result.solution);
        if (rank == 0)
          fmt::print(
              "{{\"method\": \"{}\", \"phase\": \"{}\", \"ranks\": {}, \"equator_nodes\": {}, "
              "\"unknowns\": {}, \"tets\": {}, \"mesh_seconds\": {:.3f}, "
              "\"assembly_seconds\": {:.3f}, \"solve_seconds\": {:.3f}, \"iterations\": {}, "
              "\"pressure_jump\": {:.10f}, \"max_velocity\": {:.10f}}}\n",
              method, phase, size, equator_nodes, system.dofs().n_dofs(), mesh.n_tets(),
              report.seconds, result.assembly_seconds, result.solve.seconds,
              result.solve.iterations, m[0].pressure_jump,
              analysis::max_velocity(system.dofs(), result.solution));
      }
    }
  }
  PetscFinalize();
  return 0;
}
