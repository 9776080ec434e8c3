// Small-deformation theory (eqs. 1.1, 2.59, 2.60, SPEC §3, §10) against values computed by hand.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "softflow/analysis/theory/small_deformation.hpp"
#include "softflow/common/error.hpp"

using namespace softflow::analysis::theory;

namespace {
constexpr double kDegPerRad = 180.0 / std::numbers::pi;
}  // namespace

TEST(SmallDeformation, TaylorByHand) {
  // lambda = 1: (19 + 16) / (16 + 16) = 35/32; times Ca = 0.1 -> 0.109375.
  EXPECT_NEAR(taylor_deformation(1.0, 0.1), 0.109375, 1e-15);
  // lambda = 2: 54/48 = 1.125 -> 0.1125.
  EXPECT_NEAR(taylor_deformation(2.0, 0.1), 0.1125, 1e-15);
  // lambda = 0 (bubble): 16/16 = 1; lambda -> infinity tends to 19/16.
  EXPECT_NEAR(taylor_deformation(0.0, 0.2), 0.2, 1e-15);
  EXPECT_NEAR(taylor_deformation(1e12, 1.0), 19.0 / 16.0, 1e-10);
}

TEST(SmallDeformation, ChaffeyBrennerByHand) {
  // lambda = 1: 35 * 5 / 160 = 1.09375 rad per unit Ca; Ca = 0.1 -> 0.109375
  // rad = 6.266725884...deg, theta = 38.733274116 deg.
  EXPECT_NEAR(chaffey_brenner_angle_deg(1.0, 0.1), 45.0 - 0.109375 * kDegPerRad, 1e-12);
  EXPECT_NEAR(chaffey_brenner_angle_deg(1.0, 0.1), 38.73327411575662, 1e-10);
  // lambda = 2: 54 * 7 / 240 = 1.575; Ca = 0.1 -> 45 - 9.02408527... = 35.97591472668953.
  EXPECT_NEAR(chaffey_brenner_angle_deg(2.0, 0.1), 35.97591472668953, 1e-10);
  EXPECT_DOUBLE_EQ(chaffey_brenner_angle_deg(3.0, 0.0), 45.0);
}

TEST(SmallDeformation, GrecoReducesToChaffeyBrennerWithoutElasticity) {
  for (const double lambda : {0.0, 0.5, 1.0, 2.0, 10.0}) {
    EXPECT_NEAR(greco_angle_deg(lambda, 0.07, 0.0, 0.0), chaffey_brenner_angle_deg(lambda, 0.07),
                1e-12);
  }
}

TEST(SmallDeformation, GrecoByHand) {
  // UCM drop of Fig. 2.12: lambda = 2, p_d = 0.5, p = 0. Drop coefficient
  // (9*4 + 6*8) / (8 * 3 * 54) = 84/1296 = 7/108; times p_d -> 7/216.
  // theta = 45 deg - 0.1 (1.575 + 7/216) rad = 35.79023395974899 deg.
  EXPECT_NEAR(greco_angle_deg(2.0, 0.1, 0.0, 0.5), 35.79023395974899, 1e-10);
  // Matrix term at lambda = 1: (176 + 436 + 323) / (30 * 2 * 35) = 935/2100;
  // p = 1, Ca = 0.1: 45 deg - 0.1 (1.09375 + 0.445238...) rad = 36.18224774219796.
  EXPECT_NEAR(greco_angle_deg(1.0, 0.1, 1.0, 0.0), 36.18224774219796, 1e-10);
  // Elasticity on either side lowers theta (thesis §1.2).
  EXPECT_LT(greco_angle_deg(1.0, 0.1, 0.3, 0.0), chaffey_brenner_angle_deg(1.0, 0.1));
  EXPECT_LT(greco_angle_deg(1.0, 0.1, 0.0, 0.3), chaffey_brenner_angle_deg(1.0, 0.1));
}

TEST(SmallDeformation, SecondOrderFluidsByHandAndTheirEqualRelaxationTimeIdentity) {
  for (const double lambda : {0.0, 0.5, 1.0, 2.0, 10.0})
    EXPECT_NEAR(second_order_fluid_angle_deg(lambda, 0.07, 0.0, 0.0),
                chaffey_brenner_angle_deg(lambda, 0.07), 1e-12);
  // UCM drop, lambda = 2, p_d = 0.5, Ca = 0.1: drop coefficient 3*4 / (2*3*54) = 1/27;
  // theta = 45 deg - 0.1 (1.575 + 1/54) rad = 35.86980... deg: a shift of
  // -0.1/54 rad = -0.10610 deg where eq. 2.60 as printed has -0.18568.
  EXPECT_NEAR(second_order_fluid_angle_deg(2.0, 0.1, 0.0, 0.5) - chaffey_brenner_angle_deg(2.0, 0.1),
              -0.1 / 54.0 * 180.0 / std::numbers::pi, 1e-12);
  // Matrix term at lambda = 2: (76 + 64 + 16) / (2 * 3 * 54) = 13/27, as in
  // eq. 2.60 (2340/4860); at lambda = 0 it is 1/2 where eq. 2.60 has 11/30.
  EXPECT_NEAR(second_order_fluid_angle_deg(2.0, 0.1, 1.0, 0.0), greco_angle_deg(2.0, 0.1, 1.0, 0.0),
              1e-12);
  EXPECT_NEAR(chaffey_brenner_angle_deg(0.0, 0.1) - second_order_fluid_angle_deg(0.0, 0.1, 1.0, 0.0),
              0.05 * 180.0 / std::numbers::pi, 1e-12);
  // Both phases with the same relaxation time (De_d = De_m = De; Ca p = De,
  // Ca p_d = De / lambda): the shift is -De/2 rad whatever lambda.
  const double ca = 0.05, de = 0.02;
  for (const double lambda : {0.1, 0.5, 1.0, 2.0, 7.0})
    EXPECT_NEAR(second_order_fluid_angle_deg(lambda, ca, de / ca, de / (ca * lambda)) -
                    chaffey_brenner_angle_deg(lambda, ca),
                -de / 2.0 * 180.0 / std::numbers::pi, 1e-12)
        << "lambda = " << lambda;
}

TEST(SmallDeformation, SlipDrop) {
  // alpha = 0 is Taylor's eq. 1.1.
  for (const double lambda : {0.0, 0.3, 1.0, 4.0}) {
    EXPECT_NEAR(slip_taylor_deformation(lambda, 0.05, 0.0), taylor_deformation(lambda, 0.05),
                1e-15);
  }
  // lambda = 1, alpha = 0.1: (35 + 8) / (16 * 2.5) = 43/40; alpha = 1:
  // (35 + 80) / (16 * 7) = 115/112. Slip lowers D (Fig. 2.11).
  EXPECT_NEAR(slip_taylor_deformation(1.0, 0.1, 0.1), 0.1075, 1e-15);
  EXPECT_NEAR(slip_taylor_deformation(1.0, 0.1, 1.0), 11.5 / 112.0, 1e-15);
  EXPECT_LT(slip_taylor_deformation(1.0, 0.1, 1.0), slip_taylor_deformation(1.0, 0.1, 0.1));
  // Full slip (alpha -> infinity): 80/80 = 1, the bubble's slope.
  EXPECT_NEAR(slip_taylor_deformation(1.0, 1.0, 1e12), 1.0, 1e-10);
}

TEST(SmallDeformation, RoscoeSmallCa) {
  // D = 5/4 * 0.1 = 0.125; theta = 45 deg - 0.075 rad = 40.702816536518824 deg.
  EXPECT_NEAR(roscoe_small_ca_deformation(0.1), 0.125, 1e-15);
  EXPECT_NEAR(roscoe_small_ca_angle_deg(0.1), 40.702816536518824, 1e-10);
}

TEST(SmallDeformation, KelvinVoigtSphere) {
  // mu_d / eta_m = 1, Ca_e = 0.1: D = 0.125 as Roscoe's; theta = 45 deg -
  // (2 + 3)/4 * 0.1 rad = 45 - 0.125 rad = 37.83803...; by hand
  // 0.125 * 180 / pi = 7.161972439135291.
  EXPECT_NEAR(kelvin_voigt_small_ca_deformation(0.1, 1.0), 0.125, 1e-15);
  EXPECT_NEAR(kelvin_voigt_small_ca_angle_deg(0.1, 1.0), 45.0 - 7.161972439135291, 1e-10);
  // lambda_s = 4: (8 + 3)/4 * 0.05 = 0.1375 rad = 7.878169683048820 deg.
  EXPECT_NEAR(kelvin_voigt_small_ca_angle_deg(0.05, 4.0), 45.0 - 7.878169683048820, 1e-10);
  // No viscosity: Roscoe's neo-Hookean sphere.
  EXPECT_EQ(kelvin_voigt_small_ca_angle_deg(0.1, 0.0), roscoe_small_ca_angle_deg(0.1));
  EXPECT_THROW(kelvin_voigt_small_ca_angle_deg(0.1, -1.0), softflow::InputError);
  TheoryQuery query;
  query.ca_e = 0.1;
  query.solid_viscosity_ratio = 1.0;
  const std::string table = theory_table(1.0, 0.1, query);
  EXPECT_NE(table.find("mu_d / eta_m = 1: D 0.125, theta 37.838 deg"), std::string::npos) << table;
  EXPECT_EQ(theory_table(1.0, 0.1).find("Kelvin-Voigt"), std::string::npos);
}

TEST(SmallDeformation, RejectsNegativeInput) {
  EXPECT_THROW(taylor_deformation(-1.0, 0.1), softflow::InputError);
  EXPECT_THROW(chaffey_brenner_angle_deg(1.0, -0.1), softflow::InputError);
  EXPECT_THROW(greco_angle_deg(1.0, 0.1, -1.0, 0.0), softflow::InputError);
  EXPECT_THROW(slip_taylor_deformation(1.0, 0.1, std::nan("")), softflow::InputError);
  EXPECT_THROW(roscoe_small_ca_deformation(-0.1), softflow::InputError);
}

TEST(SmallDeformation, TheoryTableNamesTheValues) {
  const std::string table = theory_table(1.0, 0.1);
  EXPECT_NE(table.find("lambda = 1, Ca = 0.1"), std::string::npos) << table;
  EXPECT_NE(table.find("0.109375"), std::string::npos) << table;  // Taylor D
  EXPECT_NE(table.find("38.7333"), std::string::npos) << table;   // Chaffey-Brenner
  EXPECT_NE(table.find("0.1075"), std::string::npos) << table;    // slip, alpha = 0.1
  EXPECT_NE(table.find("40.7028"), std::string::npos) << table;   // Roscoe
  EXPECT_THROW(theory_table(-1.0, 0.1), softflow::InputError);
}

TEST(SmallDeformation, TheoryTableEvaluatesGrecoAndRoscoeAtTheGivenElasticity) {
  // The UCM drop of Fig. 2.12: lambda = 2, p_d = 0.5, Ca = 0.1. By hand:
  // shift = -Ca p_d (9 lambda^2 + 6 lambda^3) / (8 (1 + lambda)(16 + 19 lambda))
  //       = -0.1 * 0.5 * 84 / 1296 rad = -0.18568 deg, from Chaffey-Brenner's 35.9759.
  TheoryQuery query;
  query.p_d = 0.5;
  query.ca_e = 0.2;
  const std::string table = theory_table(2.0, 0.1, query);
  EXPECT_NE(table.find("35.7902 deg (shift -0.1857 deg)"), std::string::npos) << table;
  EXPECT_NE(table.find("Ca_e = 0.2 (Roscoe): D 0.25"), std::string::npos) << table;
}

TEST(SmallDeformation, TheoryTableGivesTheSlipDropAtTheGivenSlip) {
  // lambda = 1, Ca = 0.1, alpha = 0.5: (19 + 16 + 80 * 0.5) / (16 (1 + 1 + 2.5))
  // = 75/72, so D = 0.1041666... -> "0.104167".
  TheoryQuery query;
  query.slip = 0.5;
  const std::string table = theory_table(1.0, 0.1, query);
  EXPECT_NE(table.find("  Slip drop D, slip alpha = 0.5         0.104167\n"), std::string::npos)
      << table;
  EXPECT_EQ(table.find("0.1075"), std::string::npos) << table;  // not the default alpha = 0.1
  EXPECT_EQ(table.find("alpha = 1 "), std::string::npos) << table;
  query.slip = -1.0;
  EXPECT_THROW(theory_table(1.0, 0.1, query), softflow::InputError);
}

TEST(SmallDeformation, TheoryTableGivesOldroydsEmulsionAtTheGivenVolumeFractionAndFrequency) {
  // lambda = 1, phi = 0.1, omega* = 1: eqs. A.1-A.5 by hand (test_oldroyd_emulsion.cpp)
  // G' = 0.0677538, G'' / omega = 1.02881.
  TheoryQuery query;
  query.phi = 0.1;
  query.omega_star = 1.0;
  const std::string table = theory_table(1.0, 0.1, query);
  EXPECT_NE(table.find("G' R / Gamma 0.0677538, G'' / (eta_m omega) 1.02881"), std::string::npos)
      << table;
  query.phi = 1.0;
  EXPECT_THROW(theory_table(1.0, 0.1, query), softflow::InputError);
}
