// parallel::launcher_rank and start_singleton_without_daemon: the
// environment they read and the one they leave. Each test restores the
// variables it touches (the unit tests also run under mpiexec).
#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <optional>
#include <string>

#include "softflow/parallel/singleton_start.hpp"

namespace {

constexpr const char* kIsolated = "OMPI_MCA_ess_singleton_isolated";

/// Sets or removes variables for one test, restoring them after it.
class ScopedEnvironment {
 public:
  void set(const std::string& name, const char* value) {
    if (!saved_.count(name)) {
      const char* old = std::getenv(name.c_str());
      saved_[name] = old ? std::optional<std::string>(old) : std::nullopt;
    }
    if (value)
      ::setenv(name.c_str(), value, 1);
    else
      ::unsetenv(name.c_str());
  }
  ~ScopedEnvironment() {
    for (const auto& [name, value] : saved_)
      value ? ::setenv(name.c_str(), value->c_str(), 1) : ::unsetenv(name.c_str());
  }

 private:
  std::map<std::string, std::optional<std::string>> saved_;
};

void without_launcher(ScopedEnvironment& env) {
  for (const char* v : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"}) env.set(v, nullptr);
}

}  // namespace

TEST(SingletonStart, ALauncherRankIsReadFromAnyOfTheThreeVariables) {
  ScopedEnvironment env;
  without_launcher(env);
  EXPECT_FALSE(softflow::parallel::launcher_rank().has_value());
  env.set("PMI_RANK", "3");
  EXPECT_EQ(softflow::parallel::launcher_rank(), 3);
  env.set("PMI_RANK", nullptr);
  env.set("OMPI_COMM_WORLD_RANK", "0");
  EXPECT_EQ(softflow::parallel::launcher_rank(), 0);
}

TEST(SingletonStart, WithoutALauncherMpiIsAskedToStartIsolated) {
  ScopedEnvironment env;
  without_launcher(env);
  env.set(kIsolated, nullptr);
  softflow::parallel::start_singleton_without_daemon();
  ASSERT_NE(std::getenv(kIsolated), nullptr);
  EXPECT_STREQ(std::getenv(kIsolated), "1");
}

TEST(SingletonStart, TheUsersChoiceAndALauncherAreLeftAlone) {
  ScopedEnvironment env;
  without_launcher(env);
  env.set(kIsolated, "0");  // the user's
  softflow::parallel::start_singleton_without_daemon();
  EXPECT_STREQ(std::getenv(kIsolated), "0");

  env.set(kIsolated, nullptr);
  env.set("PMIX_RANK", "1");  // under a launcher
  softflow::parallel::start_singleton_without_daemon();
  EXPECT_EQ(std::getenv(kIsolated), nullptr);
}
