// Parameter sweeps: which keys are varied, the combinations, their labels and case files.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/io/sweep_case.hpp"
#include "support/input_errors.hpp"

namespace softflow::io {
namespace {

TEST(SweepCase, AnOrdinaryCaseVariesNothing) {
  EXPECT_TRUE(sweep_parameters("[[objects]]\ncentre = [0.0, 0.0, 0.0]\n", "case.toml").empty());
}

TEST(SweepCase, EveryCombinationTheFirstParameterSlowest) {
  const Sweep s = expand_sweep(
      "[case]\nname = \"s\"\n[time]\nend = 1.0\nstep = [0.05, 0.025]\n"
      "[[objects]]\ncapillary_number = [0.1, 0.2, 0.4]\n",
      "s.toml");
  ASSERT_EQ(s.parameters.size(), 2u);
  EXPECT_EQ(s.parameters[0].path, "objects[1].capillary_number");  // sections by name
  EXPECT_EQ(s.parameters[1].path, "time.step");
  EXPECT_EQ(s.directory, "output/s");
  ASSERT_EQ(s.cases.size(), 6u);
  EXPECT_EQ(s.cases[0].label, "capillary_number_0.1__step_0.05");
  EXPECT_EQ(s.cases[1].label, "capillary_number_0.1__step_0.025");
  EXPECT_EQ(s.cases[5].label, "capillary_number_0.4__step_0.025");
  const CaseConfig& c = s.cases[5].config;
  EXPECT_EQ(*c.objects[0].capillary_number, 0.4);
  EXPECT_EQ(c.time.step, 0.025);
  EXPECT_EQ(c.time.end, 1.0);
  EXPECT_EQ(c.name, "s_capillary_number_0.4__step_0.025");
  EXPECT_EQ(c.output_directory, "output/s/capillary_number_0.4__step_0.025");
  // Each case file stands alone: it reads back as the same case.
  EXPECT_EQ(to_toml(parse_case(s.cases[5].toml_text, "x.toml")), to_toml(c));
}

TEST(SweepCase, VectorsAreVariedByListsOfVectorsAndObjectsAreNamed) {
  const Sweep s = expand_sweep(
      "[cell]\nlength = 12.0\n"
      "[[objects]]\ncentre = [[-3.0, 0.0, 0.0], [-2.5, 0.0, 0.0]]\n"
      "[[objects]]\ncentre = [3.0, 0.0, 0.0]\nviscosity_ratio = [1, 4]\n",
      "pair.toml");
  ASSERT_EQ(s.parameters.size(), 2u);
  EXPECT_EQ(s.parameters[0].name, "objects1.centre");
  EXPECT_EQ(s.parameters[1].name, "objects2.viscosity_ratio");
  ASSERT_EQ(s.cases.size(), 4u);
  EXPECT_EQ(s.cases[3].label, "objects1.centre_-2.5x0x0__objects2.viscosity_ratio_4");
  EXPECT_EQ(s.cases[3].config.objects[0].geometry.centre.x(), -2.5);
  EXPECT_EQ(s.cases[3].config.objects[1].viscosity_ratio, 4.0);
  EXPECT_TRUE(std::isnan(s.parameters[0].numbers[0]));
  EXPECT_EQ(s.parameters[1].numbers[1], 4.0);
}

std::string error_of(const std::string& text) {
  return test_support::input_error_of([&] { (void)expand_sweep(text, "s.toml"); });
}

TEST(SweepCase, ProblemsNameTheParameterAndTheCombination) {
  EXPECT_NE(
      error_of("[[objects]]\ncapillary_number = []\n")
          .find("objects[1].capillary_number = []: a swept parameter must list at least one value"),
      std::string::npos);
  const std::string e = error_of("[[objects]]\ncapillary_number = [0.1, -1.0]\n");
  EXPECT_NE(e.find("[sweep case capillary_number_-1]"), std::string::npos) << e;
  EXPECT_NE(e.find("objects[1].capillary_number = -1.0: must be > 0"), std::string::npos) << e;
  EXPECT_NE(error_of("[time\nend = 1").find("TOML syntax error"), std::string::npos);
}


// ---- issue 33, items 8 and 9 ----

TEST(SweepCase, TheSweepsNameIsCheckedLikeACasesName) {
  const std::string swept = "[[objects]]\ncapillary_number = [0.1, 0.2]\n";
  // Passed before, "" writing into output/ itself.
  EXPECT_NE(error_of("[case]\nname = \"\"\n" + swept).find("s.toml: case.name = \"\": must be a "
                                                           "non-empty name"),
            std::string::npos);
  EXPECT_NE(error_of("[case]\nname = true\n" + swept).find("case.name = true: must be a string"),
            std::string::npos);
  EXPECT_NE(error_of("[case]\nname = 5\n" + swept).find("case.name = 5: must be a string"),
            std::string::npos);
  EXPECT_NE(error_of("[case]\nname = \"  \"\n" + swept)
                .find("case.name = \"  \": must contain a character other than spaces"),
            std::string::npos);
  EXPECT_NE(error_of("[case]\nname = \"a/b\"\n" + swept).find("case.name = \"a/b\""),
            std::string::npos);
  EXPECT_NE(error_of("[output]\ndirectory = 5\n" + swept)
                .find("output.directory = 5: must be a string"),
            std::string::npos);
  const std::string e = error_of("[case]\nname = \"" + std::string(240, 'n') + "\"\n" + swept);
  EXPECT_NE(e.find("of 240 bytes: at most 239 are allowed"), std::string::npos) << e;
  EXPECT_NE(error_of("[case]\nname = [\"a\", \"b\"]\n" + swept).find("case.name = [\"a\", \"b\"]: "
                                                                   "cannot be varied"),
            std::string::npos);
  EXPECT_NE(error_of("[output]\ndirectory = [\"a\", \"b\"]\n" + swept).find("cannot be varied"),
            std::string::npos);
  EXPECT_EQ(error_of("[case]\nname = \"fine\"\n[output]\ndirectory = \"out/fine\"\n" + swept), "");
  // A file name that cannot be a name gives "sweep".
  EXPECT_EQ(expand_sweep(swept, "   .toml").name, "sweep");
}

TEST(SweepCase, ALabelTooLongForADirectoryIsRefused) {
  const std::string e = error_of("[[objects]]\ncapillary_number = [0.1, 0.2]\n[case]\nname = \"s\"\n"
                                 "[solver]\npetsc_options = [\"-a\", \"-" +
                                 std::string(240, 'b') + "\"]\n");
  EXPECT_NE(e.find("has a label of"), std::string::npos) << e;
  EXPECT_NE(e.find("at most 238 bytes"), std::string::npos) << e;
}

TEST(SweepCase, AValueListedTwiceIsRefused) {
  // Still a sweep file (softflow check and run tell it by this), refused on expansion.
  EXPECT_EQ(sweep_parameters("[[objects]]\ncapillary_number = [0.1, 0.1]\n", "s.toml").size(), 1u);
  // Ran once and gave two identical rows.
  std::string e = error_of("[[objects]]\ncapillary_number = [0.1, 0.2, 0.1]\n");
  EXPECT_NE(e.find("objects[1].capillary_number = [0.1, 0.2, 0.1]: lists 0.1 twice (values 1 and "
                   "3)"),
            std::string::npos)
      << e;
  e = error_of("[time]\nend = 1.0\nstep = [0.05, 0.050]\n");
  EXPECT_NE(e.find("time.step = [0.05, 0.05]: lists 0.05 twice"), std::string::npos) << e;
  e = error_of("[[objects]]\nviscosity_ratio = [1, 1.0]\n");
  EXPECT_NE(e.find("lists 1.0 twice"), std::string::npos) << e;
  e = error_of("[[objects]]\ncentre = [[0.0, 0.0, 0.0], [0, 0, 0]]\n");
  EXPECT_NE(e.find("objects[1].centre"), std::string::npos) << e;
  EXPECT_NE(e.find("twice"), std::string::npos) << e;
  // Different values, one directory.
  e = error_of("[solver]\npetsc_options = [\"-a b\", \"-a_b\"]\n");
  EXPECT_NE(e.find("both make the directory label '-a_b'"), std::string::npos) << e;
  EXPECT_EQ(error_of("[[objects]]\ncapillary_number = [0.1, 0.2]\n"), "");
}

}  // namespace
}  // namespace softflow::io
