#include "softflow/parallel/singleton_start.hpp"

#include <cstdlib>

namespace softflow::parallel {

std::optional<int> launcher_rank() {
  for (const char* variable : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
    if (const char* rank = std::getenv(variable)) return std::atoi(rank);
  return std::nullopt;
}

void start_singleton_without_daemon() {
  if (launcher_rank()) return;
  ::setenv("OMPI_MCA_ess_singleton_isolated", "1", /*overwrite=*/0);
}

}  // namespace softflow::parallel
