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

/* With PG_MPI_TEST_ID_BASE=B (or B:S) set when pg_mpi_init runs, the distributed pits
 * give cube cell c the global id B + S * c (pg_mpi_comm.h; S = 1 unless given) instead
 * of c: every label, tie-break and cross-rank pair then carries ids above 2^32 on a
 * small planet. The order of the ids, and so every result, is the same for any B and
 * S. With S = 2^32 every id cut to 32 bits is B mod 2^32, so any truncation merges all
 * labels and shows as a different result (test_mpi_pits.c). */
#define PG_MPI_TESTING_ID_BASE_ENV "PG_MPI_TEST_ID_BASE"

#endif
