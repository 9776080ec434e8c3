#include "softflow/simulation/step_module.hpp"

#include "softflow/fem/field.hpp"
#include "softflow/fem/mesh_transfer.hpp"

namespace softflow::simulation {

void carry_fields_over(std::span<fem::Field* const> to, std::span<fem::Field* const> from,
                       const fem::MeshTransfer& transfer) {
  for (fem::Field* f : to)
    for (fem::Field* old : from)
      if (old->name() == f->name())
        f->scatter(transfer.transfer(old->space(), f->space(), old->components(), old->gather()));
}

void StepModule::carry_over(StepModule& old, const fem::MeshTransfer& transfer) {
  const auto to = fields(), from = old.fields();
  carry_fields_over(to, from, transfer);
  restart_time_history();
}

}  // namespace softflow::simulation
