/*
 * perma-queens: count the N-queens solutions and search-tree nodes with
 * perma; under mpirun the subtrees are spread over the ranks, which steal
 * work from each other (docs/scale-out.md).  The count is checked against
 * a sequential count on the host.
 * Exit status: 0 ok, 1 a failure or a wrong count, 2 bad usage.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpi_launch.h"
#include "queens_spread.h"

static void usage(FILE *out, const char *program)
{
    fprintf(out, "usage: %s [--n N] [--depth D] [--chunk C] [--start even|rank0] [--devices LIST]\n"
                 "       [--rank-timeout S]\n\n"
                 "Counts the N-queens solutions and search-tree nodes with a perma procedure.\n"
                 "Under mpirun the subtrees below row D are spread over the ranks; a rank that\n"
                 "runs dry asks the others for work.\n\n"
                 "  --n N           board size, 1..%d (default 10)\n"
                 "  --depth D       rows the host places to cut the tree into subtrees, 0..N (default 3)\n"
                 "  --chunk C       subtrees per perma run, 1..65536 (default 16)\n"
                 "  --start S       even: each rank starts with an equal share (default);\n"
                 "                  rank0: rank 0 starts with all, the others steal\n"
                 "  --devices LIST  device list; rank r uses entry (local rank mod count)\n"
                 "  --rank-timeout S  mpirun: end the job when a rank does not answer for S seconds,\n"
                 "                  1..1e6 (default 660; a rank answers between runs of C subtrees)\n",
            program, QUEENS_MAX_N);
}

static int parse_seconds(const char *text, double *out)
{
    char *end;
    errno = 0;
    double value = strtod(text, &end);
    if (!text[0] || *end || errno || !(value >= 1.0 && value <= 1e6))
        return 0;
    *out = value;
    return 1;
}

static int parse_number(const char *text, unsigned long low, unsigned long high, unsigned *out)
{
    char *end;
    errno = 0;
    if (text[0] < '0' || text[0] > '9')
        return 0;
    unsigned long value = strtoul(text, &end, 10);
    if (errno || *end || value < low || value > high)
        return 0;
    *out = (unsigned)value;
    return 1;
}

/* 0 ok, 2 bad usage (message printed), -1 help or version shown. */
static int parse(int argc, char **argv, queens_job *job, int quiet)
{
    const char *program = argv[0];
    for (int i = 1; i < argc; ++i) {
        const char *arg = argv[i], *value = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            if (!quiet)
                usage(stdout, program);
            return -1;
        }
        if (strcmp(arg, "--version") == 0) {
            if (!quiet)
                printf("perma-queens %s\n", PERMA_VERSION_STRING);
            return -1;
        }
        int known = strcmp(arg, "--n") == 0 || strcmp(arg, "--depth") == 0 || strcmp(arg, "--chunk") == 0
                    || strcmp(arg, "--start") == 0 || strcmp(arg, "--devices") == 0
                    || strcmp(arg, "--rank-timeout") == 0;
        const char *problem = NULL;
        if (!known)
            problem = "unknown option";
        else if (!value)
            problem = "needs a value";
        else if (strcmp(arg, "--n") == 0 && !parse_number(value, 1, QUEENS_MAX_N, &job->n))
            problem = "expected a board size 1..16";
        else if (strcmp(arg, "--depth") == 0 && !parse_number(value, 0, QUEENS_MAX_N, &job->depth))
            problem = "expected rows 0..N";
        else if (strcmp(arg, "--chunk") == 0 && !parse_number(value, 1, 65536, &job->chunk))
            problem = "expected subtrees 1..65536";
        else if (strcmp(arg, "--start") == 0 && strcmp(value, "even") == 0)
            job->start = QUEENS_START_EVEN;
        else if (strcmp(arg, "--start") == 0 && strcmp(value, "rank0") == 0)
            job->start = QUEENS_START_RANK0;
        else if (strcmp(arg, "--start") == 0)
            problem = "expected even or rank0";
        else if (strcmp(arg, "--devices") == 0)
            job->devices = value;
        else if (strcmp(arg, "--rank-timeout") == 0 && !parse_seconds(value, &job->rank_timeout))
            problem = "expected seconds in 1..1e6";
        else if (strcmp(arg, "--rank-timeout") == 0 && mpi_launch_size() == 0)
            problem = "applies only to a job started by mpirun";
        if (problem) {
            if (!quiet)
                fprintf(stderr, "%s: %s%s%s%s: %s (try --help)\n", program, arg, value && known ? " '" : "",
                        value && known ? value : "", value && known ? "'" : "", problem);
            return 2;
        }
        ++i;
    }
    if (job->depth > job->n) {
        if (!quiet)
            fprintf(stderr, "%s: --depth %u: expected rows 0..%u (--n) (try --help)\n", program, job->depth,
                    job->n);
        return 2;
    }
    return 0;
}

int main(int argc, char **argv)
{
    const char *program = argc > 0 ? argv[0] : "perma-queens";
    queens_job job = { .n = 10, .depth = 3, .chunk = 16, .start = QUEENS_START_EVEN, .devices = NULL };
    /* Under mpirun every rank parses the same line; rank 0 speaks. */
    int quiet = mpi_launch_size() > 0 && mpi_launch_rank() != 0;
    int parsed = parse(argc, argv, &job, quiet);
    if (parsed != 0)
        return parsed < 0 ? 0 : 2;
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
