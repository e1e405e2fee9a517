/*
 * The C reference's full render on every core with OpenMP: what a C
 * programmer would write instead of the megakernel.  Two phases in one
 * parallel region: bound/split of the base patches (a dynamic schedule,
 * one patch at a time), each thread recording the sub-patches to dice in
 * its own list; then dice, shade and sample of all of them (a dynamic
 * schedule over chunks of consecutive sub-patches, which lie side by side
 * on screen), each thread with its own grid scratch, into one shared
 * sample buffer by an atomic minimum per sample.  The result of a sample
 * is the nearest value whatever the order, so the image and the counts
 * are those of reyes_reference_render exactly.  With occlusion culling
 * each thread sorts its sub-patches front to back, one thread merges the
 * lists, and the dice loop takes them in that order, each tested against
 * the samples the threads have written so far: the image is still the
 * single-threaded one, but which grids are skipped (occluded,
 * micropolygons) depends on the timing.
 */
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_reference_internal.h"
#include "reyes_reference_parallel.h"

/* Sub-patches a thread takes from the shared list at a time. */
#define DICE_CHUNK 8

/* One thread's state, on its own cache lines. */
typedef struct worker {
    reference_context c;
    reyes_reference_counts counts;
    reference_leaves leaves;
    size_t first;  /* where its leaves start in the shared list */
    size_t merged; /* its sorted leaves merged so far (occlusion culling) */
} __attribute__((aligned(64))) worker;

static void add_counts(reyes_reference_counts *total, const reyes_reference_counts *part)
{
    total->splits += part->splits;
    total->culled += part->culled;
    total->grids += part->grids;
    total->forced_dice += part->forced_dice;
    total->micropolygons += part->micropolygons;
    total->occluded += part->occluded;
    if (part->max_depth_seen > total->max_depth_seen)
        total->max_depth_seen = part->max_depth_seen;
}

/* The workers' sorted leaf lists merged into all, front to back. */
static void merge_leaves(worker *workers, int count, reference_leaf *all)
{
    for (int t = 0; t < count; ++t)
        workers[t].merged = 0;
    for (size_t k = 0;; ++k) {
        const reference_leaf *first = NULL;
        int from = 0;
        for (int t = 0; t < count; ++t) {
            const reference_leaves *l = &workers[t].leaves;
            size_t next = workers[t].merged;
            if (next < l->count && (!first || reference_leaf_before(&l->items[next], first))) {
                first = &l->items[next];
                from = t;
            }
        }
        if (!first)
            return;
        all[k] = *first;
        ++workers[from].merged;
    }
}

/* Both phases on `count` workers; 0, or 1 when a leaf list ran out of
 * memory. */
static int render_on(worker *workers, int count, const reyes_scene *scene, reference_leaf **all)
{
    int failed = 0;
    size_t total = 0;
#pragma omp parallel num_threads(count)
    {
        worker *w = &workers[omp_get_thread_num()];
#pragma omp for schedule(dynamic, 1) nowait
        for (size_t p = 0; p < scene->patch_count; ++p)
            reference_subdivide_patch(&w->c, (uint32_t)p);
        if (w->c.occlusion && !w->leaves.failed)
            reference_leaves_sort(w->leaves.items, w->leaves.count);
#pragma omp barrier
#pragma omp single
        {
            for (int t = 0; t < count; ++t) {
                workers[t].first = total;
                total += workers[t].leaves.count;
                failed |= workers[t].leaves.failed;
            }
            *all = failed ? NULL : malloc((total ? total : 1) * sizeof **all);
            failed |= !*all;
            if (!failed && workers[0].c.occlusion)
                merge_leaves(workers, count, *all);
        }
        if (!failed) {
            if (!w->c.occlusion && w->leaves.count) /* a thread without leaves may have no list (NULL) */
                memcpy(*all + w->first, w->leaves.items, w->leaves.count * sizeof **all);
#pragma omp barrier
#pragma omp for schedule(dynamic, DICE_CHUNK)
            for (size_t k = 0; k < total; ++k)
                reference_dice_leaf(&w->c, &(*all)[k]);
        }
    }
    return failed;
}

reyes_status reyes_reference_render_parallel(const reyes_scene *scene, const reyes_camera *camera,
                                             const reyes_options *options, unsigned threads, reyes_image *image,
                                             reyes_reference_counts *out, reyes_error *error)
{
    reference_context base;
    reyes_options full;
    reference_samples samples;
    reyes_status status = reference_render_begin(&base, &full, &samples, scene, camera, options, 1, image, out, error);
    int count = threads ? (int)threads : omp_get_max_threads();
    worker *workers = NULL;
    if (status == REYES_OK) {
        workers = aligned_alloc(64, (size_t)count * sizeof *workers);
        if (workers)
            memset(workers, 0, (size_t)count * sizeof *workers);
        else
            status = reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %d C reference threads", count);
    }
    for (int t = 0; status == REYES_OK && t < count; ++t) {
        workers[t].c = base;
        workers[t].c.counts = &workers[t].counts;
        workers[t].c.leaves = &workers[t].leaves;
        status = reference_grid_alloc(&workers[t].c, error);
    }
    if (status == REYES_OK) {
        reference_leaf *all = NULL;
        struct timespec start;
        clock_gettime(CLOCK_MONOTONIC, &start);
        int failed = render_on(workers, count, scene, &all);
        out->seconds = reference_seconds_since(&start);
        free(all);
        if (failed)
            status = reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for the sub-patches to dice");
        for (int t = 0; t < count; ++t)
            add_counts(out, &workers[t].counts);
    }
    for (int t = 0; workers && t < count; ++t) {
        free(workers[t].c.grid);
        reference_leaves_free(&workers[t].leaves);
    }
    free(workers);
    return reference_render_end(status, &samples, options, image, out);
}
