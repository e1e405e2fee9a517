/*
 * perma-queens: count the N-queens solutions and search-tree nodes with
 * perma; under mpirun the subtrees are spread over the ranks, which steal
 * work from each other (docs/scale-out.md).  The count is checked against
 * a sequential count on the host.
 * Exit status: 0 ok, 1 a failure or a wrong count, 2 bad usage.
 */
#include <stdio.h>
#include <stdlib.h>

#include <perma_cli.h>

#include "mpi_launch.h"
#include "queens_spread.h"

_Static_assert(sizeof(queens_start) == sizeof(unsigned), "--start is a choice row");

/* The command line into *job (perma_cli.h); quiet: say nothing (an MPI
 * rank other than 0). */
static perma_cli_status parse(int argc, char **argv, queens_job *job, int quiet)
{
    static const char *const starts[] = { "even", "rank0", NULL }; /* queens_start */
    int timeout_given = 0, depth_given = 0;
    char message[PERMA_CLI_MESSAGE_MAX];
    const perma_cli_option rows[] = {
        { PERMA_CLI_WHOLE("n", "N", &job->n, 1, QUEENS_MAX_N, "board size (default 10)") },
        { PERMA_CLI_WHOLE("depth", "D", &job->depth, 0, QUEENS_MAX_N,
                          "rows the host places to cut the tree into subtrees, at most N (default 3, or N if "
                          "smaller)"),
          .given = &depth_given },
        { PERMA_CLI_WHOLE("chunk", "C", &job->chunk, 1, 65536, "subtrees per perma run (default 16)") },
        { PERMA_CLI_CHOICE("start", "S", &job->start, starts,
                           "even: each rank starts with an equal share (default); rank0: rank 0 starts with all, "
                           "the others steal") },
        { PERMA_CLI_TEXT("devices", "LIST", &job->devices, "device list; rank r uses entry (local rank mod count)") },
        { PERMA_CLI_DOUBLE("rank-timeout", "S", &job->rank_timeout, 1, 1e6,
                           "mpirun: end the job when a rank does not answer for S seconds (default 660; a rank "
                           "answers between runs of C subtrees)"),
          .given = &timeout_given },
    };
    const perma_cli_table table = { "options", rows, sizeof rows / sizeof rows[0] };
    const perma_cli cli = {
        .program = argv[0],
        .synopsis = "[options]",
        .about = "Counts the N-queens solutions and search-tree nodes with a perma procedure.\n"
                 "Under mpirun the subtrees below row D are spread over the ranks; a rank that\n"
                 "runs dry asks the others for work.",
        .tables = &table,
        .table_count = 1,
        .notes = "exit status: 0 ok, 1 a failure or a wrong count, 2 bad usage",
        .quiet = quiet,
    };
    perma_cli_status status = perma_cli_parse(&cli, argc, argv, message, sizeof message);
    if (status != PERMA_CLI_OK)
        return status;
    /* The default depth fits any board; a depth given must. */
    if (!depth_given && job->depth > job->n)
        job->depth = job->n;
    if (job->depth > job->n)
        return perma_cli_fail(&cli, message, sizeof message, "--depth %u: expected rows 0..%u (--n)", job->depth,
                              job->n);
    /* An option of MPI jobs without mpirun: refused, not ignored. */
    if (timeout_given && mpi_launch_size() == 0)
        return perma_cli_fail(&cli, message, sizeof message,
                              "--rank-timeout applies only to a job started by mpirun");
    return PERMA_CLI_OK;
}

int main(int argc, char **argv)
{
    const char *program = argc > 0 ? argv[0] : "perma-queens";
    queens_job job = { .n = 10, .depth = 3, .chunk = 16, .start = QUEENS_START_EVEN, .devices = NULL };
    /* Under mpirun every rank parses the same line; rank 0 speaks. */
    int quiet = mpi_launch_size() > 0 && mpi_launch_rank() != 0;
    perma_cli_status parsed = parse(argc, argv, &job, quiet);
    if (parsed != PERMA_CLI_OK)
        return perma_cli_exit_status(parsed);
    queens_result result;
    int is_rank0 = 0;
    int code = queens_spread_run(&job, &result, &is_rank0, program);
    if (code != 0 || !is_rank0)
        return code;
    queens_counts expected = queens_count_sequential(job.n);
    int agrees = expected.solutions == result.counts.solutions && expected.nodes == result.counts.nodes;
    printf("%u-queens: %llu solutions, %llu nodes in %.3f s on %d rank%s (%zu subtrees below row %u, "
           "%u per run); sequential count %s",
           job.n, (unsigned long long)result.counts.solutions, (unsigned long long)result.counts.nodes,
           result.seconds, result.ranks, result.ranks == 1 ? "" : "s", result.units, job.depth, job.chunk,
           agrees ? "agrees\n" : "DISAGREES: ");
    if (!agrees)
        printf("%llu solutions, %llu nodes\n", (unsigned long long)expected.solutions,
               (unsigned long long)expected.nodes);
    for (int r = 0; r < result.ranks; ++r) {
        const queens_rank_report *p = &result.reports[r];
        printf("  rank %d: %llu subtrees, %llu solutions, %llu nodes in %.3f s; stole %llu times (%llu "
               "subtrees) in %llu requests, gave %llu times (%llu subtrees) [%s]\n",
               p->rank, (unsigned long long)p->units, (unsigned long long)p->counts.solutions,
               (unsigned long long)p->counts.nodes, p->seconds, (unsigned long long)p->steals,
               (unsigned long long)p->stolen_units, (unsigned long long)p->requests,
               (unsigned long long)p->gifts, (unsigned long long)p->given_units, p->device);
    }
    free(result.reports);
    return agrees ? 0 : 1;
}
