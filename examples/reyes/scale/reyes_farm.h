/*
 * Spreading a job's items over renderers: a pool hands out the items one
 * at a time (a renderer that finishes one takes the next) and assembles
 * what comes back (bucket tiles into one image; frames into PNG files).
 * A farm is a thread per OpenCL device, each with its own renderer, all
 * taking from one pool; MPI ranks take from rank 0's pool by messages
 * (reyes_mpi.h).  The first failure stops the handing out; renderers
 * finish the item they hold.
 */
#ifndef REYES_FARM_H
#define REYES_FARM_H

#include <pthread.h>

#include "reyes_job.h"
#include "reyes_progress.h"

typedef struct reyes_pool {
    const reyes_job *job;
    pthread_mutex_t lock;
    unsigned next;             /* the next item to hand out */
    unsigned delivered;        /* items delivered */
    int failed;                /* set by the first failure: hand out no more */
    reyes_status status;       /* the first failure */
    char message[REYES_MESSAGE_MAX]; /* "device 0:0/2.1: ..." */
    reyes_image image;         /* bucket jobs: the image being assembled */
    reyes_progress *progress;  /* NULL, or the progress line deliveries move (set before rendering) */
    /* Per item: the renderer that took it (-1: not handed out), the
     * seconds its renderer spent on it, and the seconds from handing out
     * to delivery as the pool saw them (a remote rank's messages included). */
    int *renderer;
    double *taken_at, *render_seconds, *turnaround;
    unsigned char *done;       /* per item: delivered (a frame: its file written) */
} reyes_pool;

reyes_status reyes_pool_init(reyes_pool *pool, const reyes_job *job, reyes_error *error);
void reyes_pool_free(reyes_pool *pool);

/* The next item for renderer `renderer` (an index the caller chooses:
 * device or rank) into *item; 0 when all are handed out or after a
 * failure. */
int reyes_pool_take(reyes_pool *pool, int renderer, unsigned *item);

/* The pixels of item `item`: {x0, y0, x1, y1} of its bucket, or the
 * whole frame; 0 when there is no such item. */
int reyes_pool_item_rect(const reyes_pool *pool, int64_t item, unsigned rect[4]);

/* Item `item` is done: its pixels rect = {x0, y0, x1, y1} in rows of
 * (x1 - x0) pixels, rgb (3 bytes each) and coverage, rendered in
 * `seconds` (< 0: unknown, the time since it was handed out).  Buckets go
 * into pool->image, frames are written to their PNG file.  An item that
 * does not exist or a rectangle that is not the item's (a rank started
 * with other options) is refused (REYES_ERR_RUNTIME). */
reyes_status reyes_pool_deliver(reyes_pool *pool, unsigned item, const unsigned rect[4],
                                const uint8_t *rgb, const uint8_t *coverage, double seconds,
                                reyes_error *error);

/* What is written so far, as a message says it: "no image written" for a
 * bucket job (the PNG comes at the end), "no frame written" or "3 of 24
 * frames written: k-0001.png to k-0002.png, k-0004.png" (the frames'
 * files, numbered as they are; " ..." when the list does not fit). */
void reyes_pool_describe_written(reyes_pool *pool, char *out, size_t size);

/* Record a failure of `who` ("device 0:0/2.1", "rank 2") unless one is
 * recorded already, and stop handing out. */
void reyes_pool_fail(reyes_pool *pool, const char *who, reyes_status status, const char *message);

/* Whether every item was delivered and nothing failed; else *error holds
 * the first failure (or says which items are missing). */
reyes_status reyes_pool_finish(reyes_pool *pool, reyes_error *error);

/* Pack pixels rect of image into rgb and coverage (rows of x1 - x0). */
void reyes_image_pack_rect(const reyes_image *image, const unsigned rect[4], uint8_t *rgb,
                           uint8_t *coverage);

/* A renderer in the pool's process: a bucket source taking from and
 * delivering to the pool as renderer `renderer`. */
typedef struct reyes_pool_client {
    reyes_pool *pool;
    int renderer;
} reyes_pool_client;

reyes_bucket_source reyes_pool_source(reyes_pool_client *client);

/* One farm thread: a renderer on `device` working from the pool. */
typedef struct reyes_farm_worker {
    reyes_pool_client client;  /* renderer index: its place in the array */
    perma_device_ref device;
    char who[96];              /* how failures name it: "device 0:0/2.1" */
    reyes_work_report report;
    reyes_progress_slot slot;  /* its place on the pool's progress line */
    pthread_t thread;
    int started;
    volatile int finished;     /* set when the thread is done */
} reyes_farm_worker;

/* Set up worker w as renderer `renderer` of the pool on `device`; `who`
 * names it in failures (NULL: "device P:D"). */
void reyes_farm_worker_init(reyes_farm_worker *w, reyes_pool *pool, int renderer,
                            const perma_device_ref *device, const char *who);
/* The thread body: make the renderer, render what the pool hands out,
 * record a failure in the pool, set w->finished. */
void *reyes_farm_worker_run(void *worker);

/* Start a thread per device (workers[0..count)). */
reyes_status reyes_farm_start(reyes_pool *pool, const perma_device_ref *devices, unsigned count,
                              reyes_farm_worker *workers, reyes_error *error);
/* Wait for them all. */
void reyes_farm_join(reyes_farm_worker *workers, unsigned count);

/* Render a whole job on these devices: start, join, finish.  Bucket jobs
 * leave the image in pool->image (the caller frees the pool). */
reyes_status reyes_farm_run(reyes_pool *pool, const perma_device_ref *devices, unsigned count,
                            reyes_farm_worker *workers, reyes_error *error);

#endif
