// `softflow converge`: one case on a sequence of meshes refined as a whole,
// and the Richardson-extrapolated steady D and theta with their error.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "softflow/io/sweep_case.hpp"
#include "softflow/simulation/sweep.hpp"

namespace softflow::simulation {

struct ConvergeOptions {
  int levels = 4;        ///< meshes, at least 3 (an order needs three; 2 with `order`), at most 8
  double factor = 1.25;  ///< refinement ratio between consecutive levels, in (1, 2]
  /// The levels' equator nodes given explicitly (ascending, 3 (2 with `order`) to 8 of them)
  /// instead of levels and factor: e.g. to step past a count gmsh cannot
  /// mesh. Far size and growth still scale by N_0 / N_k (N_0 the case's).
  std::vector<int> equator_nodes;
  /// The order of the error, known from an earlier study of the same family
  /// of meshes (the main drop's: 3): then two levels suffice, and the value
  /// is extrapolated from the finest two with it; with three or more, the
  /// observed orders are still reported, to check it.
  std::optional<double> order;
};

/// The case of `toml_text` on `levels` meshes: level k has
/// N_k = round(N_0 factor^k) equator nodes (N_0 the case's; one more if the
/// rounding repeats a count) and far_size and growth scaled by N_0 / N_k, so
/// that every element size of the mesh shrinks by the same ratio: a study
/// that refines only the interface cannot show an order (the far field's
/// error stays). One sweep parameter, mesh.equator_nodes; labels "N<N_k>";
/// run directories <output.directory>/N<N_k>. Throws InputError for a case
/// file with lists, a run without time (time.end = 0), or options out of range.
io::Sweep mesh_levels(const std::string& toml_text, const std::string& source_name,
                      const ConvergeOptions& options);

/// Runs the levels (as `softflow sweep` runs cases: resumable, N at a time,
/// sweep.md/csv of the runs), then writes in the output directory
/// The mesh size of a level is h = 1 / (the equator nodes gmsh made), which
/// differs from the count asked for by a rounding that varies from level to
/// level (21 for 20, 41 for 39): with the counts asked for, the main
/// example's orders came out 3.4, 1.3, 3.5; with the meshed ones 1.8, 2.9, 2.9.
///   converge.md, converge.csv   per level and object: N asked and meshed, far size, growth,
///                               unknowns, steps, t, steady, D, theta; per
///                               object and quantity the observed order of
///                               each consecutive triple of levels, the
///                               extrapolated value from the finest three and
///                               the error estimate of the finest level
///   converge.png                D and theta against N with the extrapolation
/// Returns the sweep's exit code (0 when every level completed).
int run_convergence(const std::filesystem::path& case_file, const ConvergeOptions& options,
                    const SweepOptions& sweep_options);

}  // namespace softflow::simulation
