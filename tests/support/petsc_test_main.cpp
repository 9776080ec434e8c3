// GoogleTest entry point that brackets the tests with PetscInitialize/Finalize.
#include <gtest/gtest.h>
#include <petscsys.h>

#include "softflow/parallel/singleton_start.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  softflow::parallel::start_singleton_without_daemon();
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 2;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  // Only rank 0 prints, so MPI runs report once.
  if (rank != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int status = RUN_ALL_TESTS();
  PetscFinalize();
  return status;
}
