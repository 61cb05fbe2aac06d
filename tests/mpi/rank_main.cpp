// The main of the programs ctest runs under mpirun (tests/mpi): MPI around GoogleTest, and the
// run failed when any rank failed. The tests use no ASSERT before a collective: a rank that left
// a test early would leave the others waiting in it.
#include <gtest/gtest.h>
#include <mpi.h>

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  testing::InitGoogleTest(&argc, argv);
  const int failed = RUN_ALL_TESTS();
  int anyFailed = 0;
  MPI_Allreduce(&failed, &anyFailed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return anyFailed;
}
