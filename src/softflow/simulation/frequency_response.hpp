// `softflow response`: the linear viscoelastic moduli of drops in a shear cell from
// one complex Stokes solve per frequency (physics::OscillatorySystem), no time
// stepping (issue 32 item 5).
#pragma once

#include <complex>
#include <filesystem>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "softflow/io/case_config.hpp"

namespace softflow::simulation {

/// A centred cube's moduli (as ResponsePoint's box_*): its side, phi, the
/// drops counted, G' R / Gamma, G'' / (eta_m omega) and Oldroyd's at its phi.
struct CubeModuli {
  double side = 0.0, phi = 0.0;
  int drops = 0;
  double storage = 0.0, loss = 0.0, oldroyd_storage = 0.0, oldroyd_loss = 0.0;
};

/// The moduli of one frequency. eta* = G* / (i omega) is complex, eta* =
/// eta' - i eta'' with G'' = omega eta', G' = omega eta''; scaled as the
/// thesis scales them: G' R / Gamma and G'' / (eta_m omega), with R and
/// Gamma those of objects[1] and omega* = omega eta_m R / Gamma.
struct ResponsePoint {
  double omega = 0.0, omega_star = 0.0;
  /// The drops' stresslets summed, S_xy = c eta_m gamma_dot V_d with V_d the
  /// drops' volume: c the emulsion's complex intrinsic viscosity.
  std::complex<double> intrinsic_viscosity;
  /// The whole cell (every drop), as a rheometer's walls measure it: the
  /// walls' shear stress over their shear rate, eta* = eta_m + sum S_xy /
  /// (V_cell gamma_dot_w) (the cell's mean 2 D_xy is the walls' shear rate:
  /// the velocity is continuous and periodic in x and z); phi = V_d / V_cell.
  double cell_phi = 0.0;
  double cell_storage = 0.0, cell_loss = 0.0;  ///< G' R / Gamma, G'' / (eta_m omega)
  /// The centred cube of bulk_stress.box_side, as `softflow moduli` averages
  /// (thesis eq. 4.1): eta* = <sigma_xy> / <2 D_xy> with the drops whose
  /// centre lies in it counted whole; empty without a cube.
  std::optional<CubeModuli> box;
  /// Oldroyd's emulsion (appendix A) at objects[1]'s lambda: c's dilute
  /// limit, and the moduli at cell_phi.
  std::complex<double> oldroyd_intrinsic_viscosity;
  double oldroyd_cell_storage = 0.0, oldroyd_cell_loss = 0.0;
  /// The cubes of ResponseOptions::cube_sides (thesis Figs. 4.4-4.5's study).
  std::vector<CubeModuli> cubes;
  double seconds = 0.0;  ///< assembly and solve
  /// The solve: 1 for LU; FGMRES iterations and the inner Stokes solves of the iterative path.
  int iterations = 0, inner_solves = 0, inner_iterations = 0;
};

struct ResponseOptions {
  /// Angular frequencies; empty: the case's flow.frequency.
  std::vector<double> frequencies;
  std::optional<std::filesystem::path> output_directory;  ///< overrides [output] directory
  /// Sides of centred cubes to average the moduli over besides
  /// bulk_stress.box_side (cubes.csv): whether a cube is the bulk.
  std::vector<double> cube_sides;
  bool quiet = false;
};

/// InputError (naming the key) for a case the linearisation about resting
/// spheres does not describe: no drops, a drop that is not a Newtonian
/// sphere with interfacial tension at rest, slip, a viscoelastic matrix, a
/// frequency that is not positive, a cube side that is not positive or does
/// not fit in the cell.
void check_response_case(const io::CaseConfig& config, const std::vector<double>& frequencies,
                         const std::vector<double>& cube_sides = {});

/// Meshes the case, solves every frequency, writes response.csv,
/// response.md, summary.json, case.toml (and response.png) atomically into
/// the output directory. Returns the points.
std::vector<ResponsePoint> run_frequency_response(const io::CaseConfig& config, const ResponseOptions& options);

}  // namespace softflow::simulation
