// Pieces every kind of run shares: rank-0 work with shared failure, meshing, solver settings.
#pragma once

#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "softflow/io/case_config.hpp"
#include "softflow/la/saddle_point_solver.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::simulation {

bool is_root();

/// Runs `work` on rank 0 only; a failure there is rethrown on every rank with
/// the same type (input / mesh / other) and message, so no rank waits forever.
void on_root_sharing_failure(const std::function<void()>& work);

struct MeshedCase {
  mesh::Mesh mesh;
  nlohmann::json report;  ///< nodes, tetrahedra, interface/equator nodes, min quality, seconds
};

/// Step 1 of every run: rank 0 meshes (gmsh is serial), every rank receives the mesh.
MeshedCase build_mesh(const io::CaseConfig& config);

la::SaddlePointSettings solver_settings(const io::CaseConfig& config);

}  // namespace softflow::simulation
