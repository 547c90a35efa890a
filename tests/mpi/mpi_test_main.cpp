// main() of librt_mpi_tests: GoogleTest inside an MPI job (alone it is a job of one rank,
// Open MPI's singleton). Only rank 0 prints the results; every rank runs every test, since
// render_mpi is collective.
#include <gtest/gtest.h>

#include <mpi.h>

int main(int argc, char** argv) {
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    ::testing::InitGoogleTest(&argc, argv);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank != 0) {
        ::testing::TestEventListeners& listeners = ::testing::UnitTest::GetInstance()->listeners();
        delete listeners.Release(listeners.default_result_printer());
    }
    const int failed = RUN_ALL_TESTS();
    // A test that failed on any rank fails the job.
    int any = failed != 0 ? 1 : 0;
    int all = 0;
    MPI_Allreduce(&any, &all, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Finalize();
    return all;
}
