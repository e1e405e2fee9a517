/* The renderer object, shared by the files of render/ (reyes_renderer.c makes it). */
#ifndef REYES_RENDERER_INTERNAL_H
#define REYES_RENDERER_INTERNAL_H

#include "reyes.h"

struct reyes_renderer {
    perma_runtime *rt;
    perma_proc procs[REYES_PROC_COUNT];
    unsigned grid;          /* the dice procedure's emit maximum depends on it */
    /* Micropolygons carry a motion per vertex (struct reyes_moving_quad):
     * created with a rotation over the shutter. */
    int vertex_motion;
    /* The samples of a tile (one ulong each), kept on the device from
     * render to render: cleared there, read back by mapping. */
    cl_mem samples;
    size_t samples_bytes;
};

/* Copy the runtime's last message into *error. */
reyes_status reyes_runtime_error(const struct reyes_renderer *r, const char *call,
                                 perma_status status, reyes_error *error);

#endif
