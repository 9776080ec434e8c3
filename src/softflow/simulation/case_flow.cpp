#include "softflow/simulation/case_flow.hpp"

#include "softflow/physics/stokes/stokes_system.hpp"

namespace softflow::simulation {

double redistribution_rate(const io::CaseConfig& config) {
  return config.interface.redistribution_factor * (config.shear_rate > 0 ? config.shear_rate : 1.0);
}

std::vector<physics::viscoelastic::Constitutive> phase_models(const io::CaseConfig& config) {
  return io::constitutive_models(config);
}

physics::StokesProblem stokes_problem(const io::CaseConfig& config, const mesh::Mesh& mesh,
                                      double t) {
  return stokes_problem(config, phase_models(config), mesh, t);
}

physics::StokesProblem stokes_problem(const io::CaseConfig& config,
                                      const std::vector<physics::viscoelastic::Constitutive>& models,
                                      const mesh::Mesh& mesh, double t) {
  physics::StokesProblem p;
  // The Newtonian viscosity, or a viscoelastic phase's solvent viscosity
  // (its polymer stress is the time loop's: physics::ViscoelasticCoupling).
  for (const auto& m : models) p.viscosity.push_back(m.solvent_viscosity());
  for (const auto& o : config.objects) p.interfacial_tension.push_back(o.interfacial_tension);
  // Navier slip, dimensional (the case's alpha is made dimensionless with R / eta_m).
  if (io::has_interface_slip(config))
    for (const auto& o : config.objects)
      p.slip.coefficient.push_back(io::navier_slip_coefficient(config, o));
  const auto walls = wall_motion(config);
  p.boundary_velocity = [walls, t](const Eigen::Vector3d& x) { return walls.velocity(x, t); };
  p.pressure_gauge_node = physics::default_pressure_gauge_node(mesh);
  p.pressure_gauge_value = 0.0;
  return p;
}

}  // namespace softflow::simulation
