// `softflow migration DIR...`: the master curves of cross-stream migration from several
// runs of one particle started at different heights (thesis §3.2.2, Figs. 3.6-3.10):
// v_p(y_p) and Delta S(y_p), the neutral heights where v_p changes sign, and the
// near-centre slope against eq. 3.8.
#pragma once

#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace softflow::simulation {

/// One row of a run's migration.csv kept for the curves.
struct MigrationPoint {
  int run = 0;             ///< index into MigrationCurves::runs
  double t = 0.0;
  double y_p = 0.0;        ///< centre height
  double y_rel = 0.0;      ///< y_p / y_p,max
  double v_p = 0.0;        ///< migration velocity
  double delta_s = 0.0;    ///< eq. 3.6
};

/// One run's mean migration over a stretch of time: the slope of y_p(t)
/// between the stretch's first and last rows. The per-step v_p swings with
/// the particle's tank-treading (measured, a Giesekus run at 0.10 H: per-step
/// v_p -4.3e-4 +- 2.2e-4 with both signs, over 2 time units -3.8e-4 to
/// -5.1e-4), so a sign change of the master curve is read from these.
struct MigrationSegment {
  int run = 0;
  double t_begin = 0.0, t_end = 0.0;
  double y_rel = 0.0;  ///< y_p / y_p,max at the stretch's middle (mean of its ends)
  double v_p = 0.0;    ///< (y_p(t_end) - y_p(t_begin)) / (t_end - t_begin)
};

/// The master curve v_p(y_rel) that the neutral heights and the quasi-steady
/// trajectory both read: the stretches' heights, increasing, with the
/// stretches at one height averaged into one node; linear between nodes.
struct MasterCurve {
  std::vector<double> y_rel;  ///< y_p / y_p,max, strictly increasing
  std::vector<double> v_p;    ///< the mean v_p of the stretches there
};

/// `segments` sorted by y_rel (as MigrationCurves::segments), merged at equal heights.
MasterCurve master_curve(const std::vector<MigrationSegment>& segments);

/// A height where the master curve v_p(y_rel) is zero: between two
/// neighbouring nodes of opposite sign (linear interpolation; `error` is half
/// their distance), or on a node whose v_p is zero (`error`: half the larger
/// distance to its neighbours).
struct NeutralHeight {
  enum class Kind {
    stable,    ///< v_p is + below and - above: particles gather there
    unstable,  ///< v_p is - below and + above
    touching,  ///< a zero node with v_p of one sign on both sides: approached, then left
    at_end,    ///< a zero node with v_p = 0 from it to an end: the side beyond was not measured
  };
  double y_rel = 0.0;
  double error = 0.0;
  Kind kind = Kind::unstable;
  bool stable() const { return kind == Kind::stable; }
};

/// How migration.md names a kind.
std::string describe(NeutralHeight::Kind kind);

/// The zeros of the master curve, lowest first.
std::vector<NeutralHeight> neutral_heights(const MasterCurve& curve);

/// How assemble_migration reads its runs.
enum class RunPairing {
  separate,  ///< every run is a start of its own
  /// Runs in pairs, a start at y_p0 > 0 and its mirror start at -y_p0, each
  /// on a mesh of its own (a run without its pair enters alone). Shear flow between walls is
  /// symmetric under the half turn about the vorticity (z) axis, which takes y_p, v_p and Delta S
  /// to minus themselves, so the pair's point-symmetric mean (q(start) - q(mirror)) / 2, row by
  /// row, keeps the particle's migration and drops the part the two meshes add in common, (q(start)
  /// + q(mirror)) / 2. A mesh error odd in y_p (both meshes graded alike towards the nearer wall)
  /// stays in the mean: only refinement removes that.
  mirror,
};

/// A start and its mirror start (RunPairing::mirror), with each one's mean
/// migration over its kept rows; or a run given without its mirror start.
struct MirrorPair {
  std::filesystem::path start;   ///< the run from y_p0 > 0 (or, alone, from any y_p0)
  std::filesystem::path mirror;  ///< the run from -y_p0; empty for a run alone
  bool paired() const { return !mirror.empty(); }
  double y_rel0 = 0.0;           ///< y_p0 / y_p,max of the start
  /// The slope of y_p(t) between the first and last kept rows of each run
  /// (v_mirror NaN for a run alone).
  double v_start = 0.0, v_mirror = 0.0;
  double v_mirror_averaged() const { return 0.5 * (v_start - v_mirror); }
  double v_meshes() const { return 0.5 * (v_start + v_mirror); }  ///< what the meshes add
};

struct MigrationCurves {
  /// The runs, or with RunPairing::mirror the starts from y_p0 > 0, one per
  /// pair (the points' and stretches' `run` index into it either way).
  std::vector<std::filesystem::path> runs;
  std::vector<MirrorPair> mirror_pairs;  ///< one per run (pair or alone) with RunPairing::mirror
  double blockage_ratio = 0.0;       ///< beta = 2R/H, of the first run (all must agree)
  double y_max = 0.0;                ///< y_p,max = H/2 - R of the first run (y_rel's unit)
  double capillary_number = 0.0;     ///< Ca_e of the first object (0 for a drop)
  double transient = 0.0;            ///< time dropped at the start of each run
  std::vector<MigrationPoint> points;  ///< every kept row, sorted by y_rel
  double segment = 0.0;                 ///< the stretches' length in time
  std::vector<MigrationSegment> segments;  ///< every run's stretches, sorted by y_rel
  std::vector<NeutralHeight> neutral;      ///< neutral_heights(master_curve(segments))
  /// Least squares v_p = slope * y_rel over |y_rel| <= 0.1 (eq. 3.7), with its
  /// point count and relative rms residual; none if fewer than 2 points.
  std::optional<double> slope;
  int slope_points = 0;
  double slope_residual = 0.0;
  /// Eq. 3.8's slope -2 beta^3 Ca_e (for a neo-Hookean particle in a Newtonian liquid).
  double theory_slope = 0.0;
};

/// Reads each directory's case.toml and migration.csv (object 1), drops the
/// rows with t < `transient` (the start, where the particle deforms from a
/// sphere and v_p is not yet the master curve's: the thesis drops "the very
/// early stages"), and assembles the curves. InputError names the directory
/// and what is wrong (no migration.csv, runs of different beta or Ca_e).
/// Each run's kept rows are cut into stretches of `segment` time units from
/// its first kept row (a last stretch shorter than half of it joins the one
/// before); the neutral heights are the zeros of their master_curve.
/// With RunPairing::mirror each run whose start y_p0 (its case's centre) has a
/// partner at -y_p0 is averaged with it (the same kept times needed), and a
/// run without one enters alone (listed so in migration.md: near the centre
/// plane the meshes' part matters, far from it less); InputError names a
/// centred start (its own mirror), two starts at one height, or a pair whose
/// times differ.
MigrationCurves assemble_migration(const std::vector<std::filesystem::path>& directories,
                                   double transient, double segment = 2.0,
                                   RunPairing pairing = RunPairing::separate);

/// The path of a particle that migrates quasi-steadily along the master curve:
/// dy_p/dt = v_p(y_p), with v_p linear between the nodes of
/// master_curve(`MigrationCurves::segments`) (the curve the neutral heights are read from),
/// integrated exactly on each piece (dt = dy / v with v linear in y: a
/// logarithm). It stands for a time-stepped trajectory when the particle's
/// shape and the flow around it settle (the transient each run drops, a few
/// 1/gamma_dot) much faster than the particle crosses the curve's features
/// (v_p ~ 1e-4 to 1e-2 gamma_dot H): short runs from a few heights then give
/// a trajectory whose time stepping would take tens of hours
/// (docs/confinement.md, "The quasi-steady trajectory", measures it against a
/// time-stepped one).
struct QuasiSteadyTrajectory {
  double y_start = 0.0;          ///< y_p / y_p,max at t = 0
  std::vector<double> t, y_rel;  ///< the path, eight points per piece of the curve
  double duration = 0.0;         ///< t at its end
  double y_end = 0.0;            ///< y_p / y_p,max at its end
  double neutral_height = std::numeric_limits<double>::quiet_NaN();  ///< y_rel it approaches, if any
  std::string ends_at;  ///< why it ends: near a stable neutral height, or the measured heights end
};

/// From y_p / y_p,max = `y_start` (within the segments' heights) until it
/// comes within `neutral_tolerance` of a neutral height y_n ahead (relative to
/// max(|y_n|, 0.1): near the centre plane, to 0.1 y_p,max) or leaves the
/// measured heights. InputError naming `option` for a start outside them, a
/// curve of fewer than two stretch heights or a non-finite stretch.
QuasiSteadyTrajectory quasi_steady_trajectory(const MigrationCurves& curves, double y_start,
                                              double neutral_tolerance = 0.01,
                                              const std::string& option = "--trajectory-from");

/// migration_curves.csv (the points), migration.md (runs, neutral heights,
/// the slope beside eq. 3.8, and the trajectory if one is given) in `out`,
/// with migration_trajectory.csv for the trajectory; migration.png by
/// scripts/plot_migration.py.
void write_migration(const MigrationCurves& curves, const std::filesystem::path& out,
                     const std::optional<QuasiSteadyTrajectory>& trajectory = std::nullopt);

}  // namespace softflow::simulation
