/* pg_mpi_testing.h - the test-only fault injection of the MPI distribution
 * (docs/mpi.md, "Failures"), library-internal.
 *
 * With the environment variable PG_MPI_TEST_FAIL_AT=RANK:SCALE set when
 * pg_mpi_synth_dist (pg_mpi.h) fills the hooks, rank RANK dies (_exit, no clean-up, as
 * a crash would) at its first exchange at that scale, after printing one line. The MPI
 * tests use it to show that a lost rank fails the whole run and leaves no output. */
#ifndef PG_MPI_TESTING_H
#define PG_MPI_TESTING_H

#define PG_MPI_TESTING_FAIL_AT_ENV "PG_MPI_TEST_FAIL_AT"

#endif
