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
    /* The polyline crack fix renders the scene's points welded
     * (reyes_weld.h): those of the last scene, known by its points'
     * address, count and hash. */
    float *welded;
    const float *welded_from;
    size_t welded_count;
    uint64_t welded_hash;
};

/* Copy the runtime's last message into *error. */
reyes_status reyes_runtime_error(const struct reyes_renderer *r, const char *call,
                                 perma_status status, reyes_error *error);

#endif
