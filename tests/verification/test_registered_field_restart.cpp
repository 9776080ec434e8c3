// A field the time loop does not know about, added to the run, is
// checkpointed, restored and written to the ParaView output with no code of
// its own in the checkpoint, restart or output paths.
//
// The field: a scalar, P1 per region (as the log-conformation components
// will be), transported by the flow in the ALE frame,
//
//   d(phi)/dt |_mesh + (u - u_m) . grad phi = 0,
//
// by physics::AleTransport (SUPG, BDF1 then BDF2) after every step; its BDF2
// history is registered too, so the restart tests both.
// A run checkpointed at step 3 and restarted must continue to the same
// field, and the same flow, as the run that never stopped.
#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "softflow/common/error.hpp"
#include "softflow/fem/field.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/io/checkpoint.hpp"
#include "softflow/io/vtu_writer.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/physics/transport/ale_transport.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/run_support.hpp"

using namespace softflow;
using Eigen::Vector3d;

namespace {

io::CaseConfig drop_case() {
  return io::parse_case(
      "[cell]\nlength = 8.0\nheight = 8.0\nwidth = 8.0\n"
      "[[objects]]\nviscosity_ratio = 1.0\ncapillary_number = 0.1\n"
      "[mesh]\nequator_nodes = 16\nfar_size = 2.0\n"
      "[time]\nstep = 0.05\nend = 1.0\n[output]\nfields = false\n",
      "registered_field");
}

/// One transport step of phi (physics::AleTransport: SUPG, BDF1 then BDF2)
/// with w = u - u_m of the step just taken.
void transport(const simulation::DropSimulation& sim, physics::AleTransport& transport, double dt) {
  const auto& mesh = sim.mesh();
  const auto& stokes = sim.stokes().dofs();
  fem::Field u(mesh, "u", stokes.field(physics::kVelocityField).space, 3);
  u.assign_from(stokes, physics::kVelocityField, sim.solution());
  fem::Field um(mesh, "u_m", stokes.field(physics::kVelocityField).space, 3);
  std::vector<double> nodal(um.dofs().n_dofs());
  for (int d = 0; d < um.dofs().n_dofs(); ++d)
    nodal[d] = sim.mesh_velocity()[um.dofs().node_of(d)](um.dofs().component_of(d));
  um.scatter(nodal);
  transport.step(u, &um, {}, dt, sim.time());
}

std::shared_ptr<fem::Space> p1_per_region(const mesh::Mesh& mesh) {
  return std::make_shared<fem::Space>(mesh, 1, fem::Continuity::per_region);
}

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  return worst;
}

}  // namespace

TEST(RegisteredField, ACheckpointCarriesItAndTheRestartContinuesToRoundOff) {
  const auto config = drop_case();
  const double dt = config.time.step;
  const auto path = std::filesystem::temp_directory_path() /
                    fmt::format("softflow_registered_field_{}.h5", ::getpid());

  // The run that never stops, checkpointed after step 3.
  simulation::DropSimulation sim(config, simulation::build_mesh(config).mesh);
  fem::Field phi(sim.mesh(), "tracer", p1_per_region(sim.mesh()), 1);
  phi.interpolate([](const Vector3d& x, int region) {
    return Eigen::VectorXd::Constant(1, x.y() + 0.3 * x.x() * x.z() + 2.0 * region);
  });
  sim.add_field(phi);
  physics::AleTransport phi_transport(phi);
  sim.registry().add(phi_transport.state_part());  // its BDF2 history
  const auto initial = phi.gather();
  io::Checkpoint checkpoint;
  for (int n = 1; n <= 6; ++n) {
    sim.step();
    transport(sim, phi_transport, dt);
    if (n == 3) {
      sim.save(checkpoint);
      checkpoint.softflow_version = SOFTFLOW_VERSION;
      checkpoint.case_toml = io::to_toml(config);
      io::write_checkpoint(path, checkpoint);
    }
  }
  EXPECT_TRUE(checkpoint.state.contains("fields/tracer/values"));
  EXPECT_TRUE(checkpoint.state.contains("transport/tracer/previous"));
  const auto phi_end = phi.gather();
  // The flow moved the tracer: the test compares something that changed.
  EXPECT_GT(max_difference(initial, phi_end), 1e-3);

  // The restarted run: a new simulation and a new field, registered the
  // same way, restored from the file.
  const auto saved = io::read_checkpoint(path);
  simulation::DropSimulation restarted(config, saved.reference_mesh);
  fem::Field psi(restarted.mesh(), "tracer", p1_per_region(restarted.mesh()), 1);
  restarted.add_field(psi);
  physics::AleTransport psi_transport(psi);
  restarted.registry().add(psi_transport.state_part());
  restarted.restore(saved);
  EXPECT_EQ(psi_transport.steps(), 3);
  EXPECT_EQ(restarted.steps(), 3);
  for (int n = 4; n <= 6; ++n) {
    restarted.step();
    transport(restarted, psi_transport, dt);
  }
  EXPECT_LT(max_difference(psi.gather(), phi_end), 1e-10);
  {
    // Without its history registered the transport restarts with BDF1 and
    // lands elsewhere: what the registration is for (and what the check
    // above would catch).
    simulation::DropSimulation forgetful(config, saved.reference_mesh);
    fem::Field chi(forgetful.mesh(), "tracer", p1_per_region(forgetful.mesh()), 1);
    forgetful.add_field(chi);
    physics::AleTransport chi_transport(chi);
    forgetful.restore(saved);
    for (int n = 4; n <= 6; ++n) {
      forgetful.step();
      transport(forgetful, chi_transport, dt);
    }
    EXPECT_GT(max_difference(chi.gather(), phi_end), 1e-6);
  }
  EXPECT_LT(max_difference(restarted.solution(), sim.solution()), 1e-10);
  EXPECT_LT((restarted.mesh().nodes.back() - sim.mesh().nodes.back()).norm(), 1e-12);
  std::filesystem::remove(path);

  // The ParaView output carries the added field next to velocity and
  // pressure, per region (P1 per region: its own value on each side).
  const auto sources = restarted.output_fields();
  ASSERT_EQ(sources.size(), 2u);
  for (int region : {0, 1}) {
    const auto piece = io::extract_subdomain(restarted.mesh(), sources, region);
    const auto& tracer = piece.field("tracer");
    ASSERT_EQ(tracer.values.size(), piece.points.size());
    EXPECT_NO_THROW((void)piece.field("velocity"));
    // The drop's copy started at y + 0.3 x z + 2: its values stay near that.
    double mean = 0.0;
    for (double v : tracer.values) mean += v / tracer.values.size();
    if (region == 1) {
      EXPECT_NEAR(mean, 2.0, 0.5);
    }
  }
}

TEST(RegisteredField, ARestartWithoutTheFieldItWasSavedWithIsRefusedByName) {
  // A checkpoint of a run that had a field cannot silently restart one that
  // expects another: the missing entry is named.
  StateRecord record;
  record.set("fields/other/values", std::vector<double>{1.0});
  const auto config = drop_case();
  const auto mesh = simulation::build_mesh(config).mesh;
  fem::Field phi(mesh, "tracer", p1_per_region(mesh), 1);
  const auto part = fem::state_part(phi);
  try {
    part.restore(record, part.name + "/");
    FAIL() << "a missing field was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fields/tracer/values"), std::string::npos) << e.what();
  }
}
