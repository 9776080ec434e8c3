// Peak memory of the ranks of a run, for summaries and the scaling benchmark.
#pragma once

#include <mpi.h>

namespace softflow::parallel {

/// The largest resident set each process has had so far (getrusage's
/// ru_maxrss), over the ranks of `comm`.
struct PeakMemory {
  double largest_rank_mb = 0.0;  ///< the largest rank's peak
  double total_mb = 0.0;         ///< the ranks' peaks summed
};

/// Collective over `comm`.
PeakMemory peak_memory(MPI_Comm comm);

}  // namespace softflow::parallel
