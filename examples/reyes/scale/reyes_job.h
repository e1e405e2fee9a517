/*
 * A render job of reyes-render, split into items that any renderer may
 * take: the buckets of one image, or the frames of an animation.  The
 * same job runs on one device, on several devices of one process
 * (reyes_farm.h) or on the ranks of an MPI job (reyes_mpi.h); the pieces
 * make the same bytes whoever renders them.
 */
#ifndef REYES_JOB_H
#define REYES_JOB_H

#include <stdint.h>
#include <stdio.h>

#include "reyes_cli.h"

typedef struct reyes_job {
    reyes_scene scene;         /* frame 0's */
    reyes_camera camera;       /* frame 0's */
    reyes_options options;     /* bucket_source and device are set per renderer */
    const char *output;        /* the PNG; frames: NAME-0001.png ... from NAME.png */
    unsigned frames;           /* 0: one image, its buckets are the items */
    float orbit_deg;           /* frames: the camera's turn over all frames */
    unsigned items;            /* buckets, or frames */
    unsigned bucket_columns;   /* of the image (1 unbucketed) */
    /* Model m (of the command line's) is patches [model_end[m - 1],
     * model_end[m]) of the scene (from 0 for the first); 0 models: the
     * built-in scene. */
    const char **models;
    size_t model_count;
    size_t *model_end;
    char framing_note[256];    /* what automatic framing left out, for the user ("" if nothing) */
} reyes_job;

/* Build the job of a command line: the scene (models or the built-in
 * one), the camera, the items.  Free with reyes_job_free. */
reyes_status reyes_job_init(reyes_job *job, const reyes_cli *cli, reyes_error *error);
void reyes_job_free(reyes_job *job);

/* Print what the user should know about the job (what framing left out). */
void reyes_job_print_notes(const reyes_job *job, FILE *out);

/* Whether the job's files can be written (the image, or the first frame,
 * and stats_path if not NULL), checked before rendering: a bad path fails
 * at once, not after the work. */
reyes_status reyes_job_check_outputs(const reyes_job *job, const char *stats_path, reyes_error *error);

/* Pixels [x0,x1) x [y0,y1) of bucket `item` (bucket jobs). */
void reyes_job_bucket_rect(const reyes_job *job, unsigned item, unsigned rect[4]);

/* The file of frame `frame` (0-based): "NAME-0001.png" for output
 * "NAME.png" (the extension, if any, is kept at the end). */
void reyes_job_frame_path(const reyes_job *job, unsigned frame, char *path, size_t size);

/* The scene and camera of frame `frame`: the scene carried along the
 * motion options for `frame` shutters (each frame's shutter starts where
 * the last one closed), the camera turned by frame * orbit / frames
 * degrees about the vertical axis through its target.  Free the scene. */
reyes_status reyes_job_frame(const reyes_job *job, unsigned frame, reyes_scene *scene,
                             reyes_camera *camera, reyes_error *error);

/* What one renderer did. */
typedef struct reyes_work_report {
    char device[64];           /* "0:0", "0:0/2.1" */
    char summary[256];         /* the runtime's device line */
    int rank;                  /* MPI rank; 0 in one process */
    unsigned items;            /* buckets or frames rendered */
    double seconds;            /* wall time from its start to its last item */
    double create_seconds;     /* making its renderer (registering the procedures) */
    double first_seconds;      /* from its start to its first bucket request: building the
                                  program (from the OpenCL cache) and the stitching pass */
    uint64_t grids, micropolygons, samples_written;
} reyes_work_report;

/* Render the items `source` hands out with `renderer` (made for
 * job->options on some device): one reyes_render with the source as its
 * bucket source (buckets), or a render per frame handed to
 * source->done whole (frames).  Fills the counts of *report. */
reyes_status reyes_job_work(const reyes_job *job, reyes_renderer *renderer,
                            const reyes_bucket_source *source, reyes_work_report *report,
                            reyes_error *error);

/* Copy pixels [x0,x1) x [y0,y1) of `from` into `to` (same size). */
void reyes_image_copy_rect(reyes_image *to, const reyes_image *from, unsigned x0, unsigned y0,
                           unsigned x1, unsigned y1);

#endif
