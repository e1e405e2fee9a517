/* Command-line parsing of reyes-render, table-driven (the table: reyes_cli_options.c). */
#ifndef REYES_CLI_H
#define REYES_CLI_H

#include <stddef.h>

#include "reyes.h"

#define REYES_CLI_OK 0
#define REYES_CLI_USAGE 2 /* the exit code for bad usage */

typedef struct reyes_cli {
    reyes_options render;
    const char **models;    /* model paths from argv (the array is allocated) */
    size_t model_count;
    const char *output;     /* PNG path */
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
    int help, version;
    char displace_map[4096]; /* --displace png:FILE:A (render.displace_map points here) */
} reyes_cli;

/* Parse argv into *cli.  Returns REYES_CLI_OK or REYES_CLI_USAGE with a
 * message in `message`.  Free with reyes_cli_free. */
int reyes_cli_parse(int argc, char **argv, reyes_cli *cli, char *message, size_t message_size);
void reyes_cli_free(reyes_cli *cli);

/* The value of option `name` (without dashes) when it is a flag ("on" or
 * "off") or a choice of names (the name, e.g. "stitch"), into out; 0 when
 * it is neither (an option with its own parser) or no option. */
int reyes_cli_field_text(const reyes_cli *cli, const char *name, char *out, size_t size);

/* The --help text. */
void reyes_cli_usage(FILE *out, const char *program);

#endif
