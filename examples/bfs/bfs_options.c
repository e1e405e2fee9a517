/* Command-line parsing of the bfs program. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "bfs_options.h"

void bfs_print_usage(FILE *out)
{
    fprintf(out,
        "usage: perma-bfs [options] EDGE_FILE\n"
        "       perma-bfs [options] --generate N\n"
        "Breadth-first levels from a source vertex with perma procedures.\n"
        "EDGE_FILE has one edge 'u v' per line (vertex ids from 0); '#' starts a comment.\n"
        "  --generate N          a preferential-attachment (power-law) graph of N vertices\n"
        "  --degree M            edges per new vertex when generating (default 4)\n"
        "  --seed S              generator seed (default 1)\n"
        "  --source V            start vertex (default 0)\n"
        "  --directed            edges go from u to v only (default: both ways)\n"
        "  -o FILE               write 'vertex level' lines (-1: unreached)\n"
        "  --technique NAME      megakernel, kernel-per-procedure, bounded-batches\n"
        "  --strategy NAME       shared, stealing, donation, stealing-donation (megakernel)\n"
        "  --groups N            persistent work-groups (default: automatic)\n"
        "  --stats               print the runtime's statistics\n"
        "  --compare             time the sequential C BFS and every technique and strategy\n"
        "  --repeats N           runs per version in --compare, best is reported (default 3)\n"
        "  --help                this text\n"
        "  --version             the version\n"
        "Exit status: 0 ok, 1 runtime or file failure (a bad edge file), 2 bad usage.\n");
}

static bfs_status usage(char *message, size_t size, const char *option, const char *value,
                        const char *expected)
{
    snprintf(message, size, "perma-bfs: %s '%s': expected %s", option, value, expected);
    return BFS_ERR_USAGE;
}

static int parse_number(const char *text, unsigned long long lo, unsigned long long hi,
                        unsigned long long *out)
{
    if (!text[0] || text[0] == '-' || text[0] == '+')
        return 0;
    char *end;
    errno = 0;
    unsigned long long v = strtoull(text, &end, 10);
    if (errno || *end || v < lo || v > hi)
        return 0;
    *out = v;
    return 1;
}

static int parse_unsigned(const char *text, unsigned long long lo, unsigned long long hi, unsigned *out)
{
    unsigned long long v;
    if (!parse_number(text, lo, hi, &v))
        return 0;
    *out = (unsigned)v;
    return 1;
}

static int is_flag(const char *opt, bfs_options *o)
{
    if (strcmp(opt, "--help") == 0 || strcmp(opt, "-h") == 0)
        o->help = 1;
    else if (strcmp(opt, "--version") == 0)
        o->version = 1;
    else if (strcmp(opt, "--compare") == 0)
        o->compare = 1;
    else if (strcmp(opt, "--directed") == 0)
        o->directed = 1;
    else if (strcmp(opt, "--stats") == 0)
        o->stats = 1;
    else
        return 0;
    return 1;
}

/* An option with a value; a bad value is a usage error naming the option. */
static bfs_status set_value(const char *opt, const char *v, bfs_options *o, char *message, size_t size)
{
    if (strcmp(opt, "--generate") == 0) {
        if (!parse_unsigned(v, 2, BFS_MAX_VERTICES, &o->generate))
            return usage(message, size, opt, v, "a vertex count 2..100000000");
    } else if (strcmp(opt, "--degree") == 0) {
        if (!parse_unsigned(v, 1, 1000, &o->degree))
            return usage(message, size, opt, v, "1..1000");
    } else if (strcmp(opt, "--seed") == 0) {
        if (!parse_number(v, 0, UINT64_MAX, &o->seed))
            return usage(message, size, opt, v, "a non-negative integer");
    } else if (strcmp(opt, "--source") == 0) {
        if (!parse_unsigned(v, 0, BFS_MAX_VERTICES - 1, &o->source))
            return usage(message, size, opt, v, "a vertex id");
    } else if (strcmp(opt, "--groups") == 0) {
        if (!parse_unsigned(v, 1, 4096, &o->run.work_groups))
            return usage(message, size, opt, v, "1..4096");
    } else if (strcmp(opt, "--repeats") == 0) {
        if (!parse_unsigned(v, 1, 100, &o->repeats))
            return usage(message, size, opt, v, "1..100");
    } else if (strcmp(opt, "--technique") == 0) {
        if (perma_technique_parse(v, &o->run.schedule.technique) != PERMA_OK)
            return usage(message, size, opt, v, "megakernel, kernel-per-procedure or bounded-batches");
    } else if (strcmp(opt, "--strategy") == 0) {
        if (perma_strategy_parse(v, &o->run.schedule.strategy) != PERMA_OK)
            return usage(message, size, opt, v, "shared, stealing, donation or stealing-donation");
    } else if (strcmp(opt, "-o") == 0) {
        o->output = v;
    } else {
        snprintf(message, size, "perma-bfs: unknown option '%s' (try --help)", opt);
        return BFS_ERR_USAGE;
    }
    return BFS_OK;
}

bfs_status bfs_parse_options(int argc, char **argv, bfs_options *o, char *message, size_t size)
{
    *o = (bfs_options){ .degree = 4, .seed = 1, .repeats = 3 };
    for (int i = 1; i < argc; ++i) {
        const char *opt = argv[i];
        if (is_flag(opt, o))
            continue;
        if (opt[0] != '-') {
            if (o->edge_file) {
                snprintf(message, size, "perma-bfs: two edge files given ('%s' and '%s')", o->edge_file, opt);
                return BFS_ERR_USAGE;
            }
            o->edge_file = opt;
            continue;
        }
        if (i + 1 >= argc) {
            snprintf(message, size, "perma-bfs: %s needs a value (try --help)", opt);
            return BFS_ERR_USAGE;
        }
        bfs_status st = set_value(opt, argv[++i], o, message, size);
        if (st != BFS_OK)
            return st;
    }
    if (!o->help && !o->version && !o->edge_file == !o->generate) {
        snprintf(message, size, "perma-bfs: give either an edge file or --generate N (try --help)");
        return BFS_ERR_USAGE;
    }
    if (o->generate && o->degree >= o->generate) {
        snprintf(message, size, "perma-bfs: --degree %u must be below --generate %u", o->degree, o->generate);
        return BFS_ERR_USAGE;
    }
    return BFS_OK;
}
