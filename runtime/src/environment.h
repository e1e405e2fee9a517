/* environment.h: every PERMA_* environment variable the runtime reads,
 * read in one place (environment.c) when a runtime is created. */
#ifndef PERMA_ENVIRONMENT_H
#define PERMA_ENVIRONMENT_H

#include "perma.h"

#include <stdbool.h>
#include <stddef.h>

/* Room for a path or a device list from the environment. */
#define PERMA_SETTING_MAX 4096

typedef struct perma_settings {
    bool debug;                 /* PERMA_DEBUG set, not "0": one group, -DPERMA_DEBUG */
    char trace[PERMA_SETTING_MAX];  /* PERMA_TRACE: the trace file ("": none) */
    char device[PERMA_SETTING_MAX]; /* PERMA_DEVICE: a device list ("": none) */
    /* PERMA_LOCAL_MEMORY_LIMIT in bytes (0: unset); a value that is not
     * one is an error, local_memory_error, when the config sets none. */
    size_t local_memory_limit;
    perma_error local_memory_error;
    bool build_log;             /* PERMA_BUILD_LOG set, not "0": show every build's whole log */
    char dump_program[PERMA_SETTING_MAX]; /* PERMA_DUMP_PROGRAM: write the generated program there */
    char cache_dir[PERMA_SETTING_MAX];    /* PERMA_CACHE_DIR ("": the default; "off", "0": none) */
    bool cache_dir_set;         /* PERMA_CACHE_DIR is set (even to "") */
    double cache_min_seconds;   /* PERMA_CACHE_MIN_SECONDS (1 when unset or not a number) */
    /* PERMA_STOP_GRACE: the seconds a kernel told to stop gets before the
     * run is given up (watchdog.c; 10 when unset or empty); a value that is
     * not one is an error, stop_grace_error, at perma_create. */
    double stop_grace;
    perma_error stop_grace_error;
    bool check_bounds;          /* PERMA_CHECK_BOUNDS set, not "0": guard words after host buffers (buffers.c) */
} perma_settings;

/* Read them all. */
void perma_settings_read(perma_settings *out);
/* PERMA_DEVICE alone (device lists without a runtime); "" when unset. */
const char *perma_settings_device(char *out, size_t size);

#endif
