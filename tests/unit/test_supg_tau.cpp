// The SUPG parameters of fem/supg.hpp: the steady one of pure transport and
// the transient one a time-stepped transport uses by default.
#include <cmath>

#include <gtest/gtest.h>

#include "softflow/fem/supg.hpp"

using namespace softflow;

TEST(SupgTau, SteadyPureTransportIsHalfTheElementCrossingTime) {
  EXPECT_DOUBLE_EQ(fem::supg_tau(0.3, 2.0, 0.0), 0.3 / 4.0);
  EXPECT_EQ(fem::supg_tau(0.3, 0.0, 0.0), 0.0);  // no transport, no streamline term
}

TEST(SupgTau, TransientIsNeverAboveHalfTheStep) {
  const double h = 0.3;
  for (double speed : {1e-8, 1e-3, 0.1, 1.0, 10.0})
    for (double dt : {1e-4, 1e-2, 0.1, 1.0}) {
      const double steady = fem::supg_tau(h, speed, 0.0);
      const double tau = fem::transient_supg_tau(steady, dt);
      EXPECT_LE(tau, 0.5 * dt * (1.0 + 1e-15)) << "speed " << speed << ", dt " << dt;
      EXPECT_LE(tau, steady * (1.0 + 1e-15));
      // 1 / tau^2 = 1 / tau_steady^2 + (2 / dt)^2
      EXPECT_NEAR(1.0 / (tau * tau), 1.0 / (steady * steady) + 4.0 / (dt * dt),
                  1e-12 * (1.0 / (tau * tau)));
    }
}

TEST(SupgTau, TransientTendsToTheSteadyOneAtLongStepsAndToHalfTheStepAtSlowTransport) {
  const double steady = fem::supg_tau(0.3, 1.0, 0.0);  // 0.15
  EXPECT_NEAR(fem::transient_supg_tau(steady, 1e6), steady, 1e-12);
  const double dt = 0.01;
  EXPECT_NEAR(fem::transient_supg_tau(fem::supg_tau(0.3, 1e-9, 0.0), dt), dt / 2, 1e-15);
  EXPECT_EQ(fem::transient_supg_tau(0.0, dt), 0.0);
}
