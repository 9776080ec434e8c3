#include "softflow/parallel/singleton_start.hpp"

#include <charconv>
#include <cstdlib>
#include <cstring>
#include <system_error>

namespace softflow::parallel {

std::optional<int> launcher_rank() {
  for (const char* variable : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
    if (const char* rank = std::getenv(variable)) {
      int value = -1;
      const char* end = rank + std::strlen(rank);
      const auto [stop, error] = std::from_chars(rank, end, value);
      return error == std::errc() && stop == end && value >= 0 ? value : -1;
    }
  return std::nullopt;
}

void start_singleton_without_daemon() {
  if (launcher_rank()) return;
  ::setenv("OMPI_MCA_ess_singleton_isolated", "1", /*overwrite=*/0);
}

}  // namespace softflow::parallel
