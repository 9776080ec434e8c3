// The module types a run knows: one line each. A new module is its own file
// (a StepModule) plus its line here.
#include <algorithm>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/simulation/modules/bulk_stress_module.hpp"
#include "softflow/simulation/modules/migration_module.hpp"
#include "softflow/simulation/modules/slip_module.hpp"
#include "softflow/simulation/modules/viscoelastic_module.hpp"
#include "softflow/simulation/step_module.hpp"

namespace softflow::simulation {

namespace {

template <class M>
ModuleType built_in(std::string name, std::function<std::string()> columns) {
  return {std::move(name), [](const ModuleSetup& s) { return M::wanted(s); },
          [](const ModuleSetup& s) -> std::unique_ptr<StepModule> { return std::make_unique<M>(s); },
          std::move(columns)};
}

std::vector<ModuleType>& types() {
  // In the order a run steps them (and restores their state).
  static std::vector<ModuleType> list{
      built_in<ViscoelasticModule>("viscoelastic", [] { return stress_table().markdown(); }),
      built_in<SlipModule>("slip", [] { return slip_table().markdown(); }),
      built_in<MigrationModule>("migration", [] { return migration_table().markdown(); }),
      built_in<BulkStressModule>("bulk_stress", [] { return bulk_stress_table().markdown(); }),
  };
  return list;
}

}  // namespace

const std::vector<ModuleType>& module_types() { return types(); }

void register_module_type(ModuleType type) {
  auto& list = types();
  if (std::any_of(list.begin(), list.end(), [&](const ModuleType& t) { return t.name == type.name; }))
    throw Error(fmt::format("a module type named '{}' is registered already", type.name));
  list.push_back(std::move(type));
}

std::vector<std::unique_ptr<StepModule>> make_modules(const ModuleSetup& setup) {
  std::vector<std::unique_ptr<StepModule>> modules;
  for (const auto& type : module_types())
    if (type.wanted(setup)) modules.push_back(type.make(setup));
  return modules;
}

}  // namespace softflow::simulation
