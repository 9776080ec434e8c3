#include "softflow/parallel/memory.hpp"

#include <sys/resource.h>

namespace softflow::parallel {

PeakMemory peak_memory(MPI_Comm comm) {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double mine = static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports kB
  PeakMemory p;
  MPI_Allreduce(&mine, &p.largest_rank_mb, 1, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(&mine, &p.total_mb, 1, MPI_DOUBLE, MPI_SUM, comm);
  return p;
}

}  // namespace softflow::parallel
