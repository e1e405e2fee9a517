/* Command-line parsing of reyes-render with the engine of perma's programs
 * (perma_cli.h); the option table: reyes_cli_options.c. */
#ifndef REYES_CLI_H
#define REYES_CLI_H

#include <perma_cli.h>
#include <stddef.h>

#include "reyes.h"

typedef struct reyes_cli {
    reyes_options render;
    const char **models;    /* model paths from argv (the array is allocated) */
    size_t model_count;
    const char *output;     /* PNG path */
    unsigned size[2], bucket[2]; /* --size, --bucket (then in render) */
    const char *stats_path; /* NULL: no statistics file */
    int has_camera;
    float camera[6];        /* eye x y z, target x y z */
    float fov_deg;
    int reference;          /* also run the C reference of bound/split/dice */
    /* --bound means the tiered criterion's largest bound with it;
     * --epsilon and --lambda without it are refused. */
    int bound_given, flatness_given;
    /* --shading-rate R dices to that rate (at most --grid per side);
     * --grid alone, --crack-fix wedge and --reference dice fixed grids;
     * otherwise the rate is 1. */
    int grid_given, shading_rate_given;
    /* Without --crack-fix: polyline with a shading rate and no
     * displacement, else stitch. */
    int crack_fix_given;
    /* Scale-out (docs/scale-out.md): a device list to spread buckets or
     * frames over (NULL: one device), an animation of `frames` frames
     * (0: one image) turning the camera by orbit_deg over all of them. */
    const char *devices;
    unsigned frames;
    float orbit_deg;
    int orbit_given;
    /* MPI: rank 0 ends the job when a rank holds an item this long, a
     * rank when rank 0 does not answer this long (seconds; 0: 660, the
     * runtime's watchdog and a minute). */
    float rank_timeout;
    /* MPI: rank 0 only hands out and gathers (a head node); the others
     * render. */
    int coordinator_only;
    /* --progress: the progress line on stderr even when it is not a
     * terminal; --quiet: nothing but errors. */
    int progress, quiet;
    char displace_map[4096]; /* --displace png:FILE:A (render.displace_map points here) */
} reyes_cli;

/* Parse argv into *cli, printing nothing: PERMA_CLI_OK; PERMA_CLI_HELP or
 * PERMA_CLI_VERSION (--help, --version); or PERMA_CLI_USAGE with the
 * complaint in `message`.  Free with reyes_cli_free (whatever it returned). */
perma_cli_status reyes_cli_parse(int argc, char **argv, reyes_cli *cli, char *message, size_t size);
void reyes_cli_free(reyes_cli *cli);

/* Longest file name of a frame (reyes_cli_frame_path). */
#define REYES_CLI_PATH_MAX 4200

/* The file of frame `frame` (0-based) of output `output`: "NAME-0001.png"
 * for "NAME.png" (the extension, if any, is kept at the end). */
void reyes_cli_frame_path(const char *output, unsigned frame, char *path, size_t size);

/* The files of a parsed command line, before any work: no output may be
 * another output (image or frame, --stats, PERMA_TRACE) or an input (a
 * model, the --displace map); PERMA_CLI_USAGE with the message naming
 * both (perma_check_distinct_files) otherwise. */
perma_cli_status reyes_cli_check_files(const reyes_cli *cli, char *message, size_t size);

/* The value of option `name` (without dashes) when it is a flag ("on" or
 * "off") or a choice of names (the name, e.g. "stitch"), into out; 0 when
 * it is neither (an option with its own parser) or no option. */
int reyes_cli_field_text(const reyes_cli *cli, const char *name, char *out, size_t size);

/* The --help text, `program` naming the program. */
void reyes_cli_usage(FILE *out, const char *program);

#endif
