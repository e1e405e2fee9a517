/*
 * The settings that decide a job's image and its items, as name, text and
 * digest: the models (their control points and colours as loaded) and
 * every option that changes the pixels or how the image is cut into
 * buckets or frames.  The ranks of an MPI job compare them at start-up and
 * refuse to render when one differs (reyes_mpi.c): a rank started with
 * another size would send tiles that do not fit, another model a mixed
 * image.  Options that only change where or how fast the job runs
 * (--devices, the schedule, --groups, --rank-timeout) or what rank 0 alone
 * does (-o, --stats) are not settings: every schedule and device of one
 * OpenCL implementation renders the same bytes (docs/scale-out.md).
 */
#ifndef REYES_SETTINGS_H
#define REYES_SETTINGS_H

#include <stddef.h>
#include <stdint.h>

#include "reyes_job.h"

typedef struct reyes_setting {
    char name[40];     /* "--size", "models", "model 2" */
    char value[88];    /* as a message shows it: "64x64", "teapot.bpt (32 patches)" (may be cut) */
    uint64_t digest;   /* of the whole value: a model's control points and colours */
} reyes_setting;

/* The settings of `job` (made from `cli`): a new array (free()) and its
 * length in *count; NULL when out of memory. */
reyes_setting *reyes_job_settings(const reyes_job *job, const reyes_cli *cli, size_t *count);

/* The setting called `name`, or NULL. */
const reyes_setting *reyes_settings_find(const reyes_setting *settings, size_t count, const char *name);

/* Settings are matched by name.  Returns the index in `a` of its first
 * setting that `b` lacks or has with another digest, a_count when only
 * `b` has settings `a` lacks, or SIZE_MAX when they agree; *differing (if
 * not NULL) counts the differing settings. */
size_t reyes_settings_compare(const reyes_setting *a, size_t a_count, const reyes_setting *b,
                              size_t b_count, size_t *differing);

#endif
