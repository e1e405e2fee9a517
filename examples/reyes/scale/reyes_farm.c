/* The item pool and the farm of device threads (reyes_farm.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "reyes_farm.h"
#include "reyes_interrupt.h"

reyes_status reyes_pool_init(reyes_pool *pool, const reyes_job *job, reyes_error *error)
{
    memset(pool, 0, sizeof *pool);
    pool->job = job;
    pthread_mutex_init(&pool->lock, NULL);
    size_t items = job->items ? job->items : 1;
    pool->renderer = malloc(items * sizeof *pool->renderer);
    pool->taken_at = calloc(items, sizeof *pool->taken_at);
    pool->render_seconds = calloc(items, sizeof *pool->render_seconds);
    pool->turnaround = calloc(items, sizeof *pool->turnaround);
    pool->done = calloc(items, 1);
    if (!pool->renderer || !pool->taken_at || !pool->render_seconds || !pool->turnaround || !pool->done) {
        reyes_pool_free(pool);
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %u items", job->items);
    }
    for (size_t k = 0; k < items; ++k)
        pool->renderer[k] = -1;
    if (job->frames)
        return REYES_OK;
    size_t pixels = (size_t)job->options.width * job->options.height;
    pool->image.width = job->options.width;
    pool->image.height = job->options.height;
    pool->image.rgb = calloc(pixels, 3);
    pool->image.coverage = calloc(pixels, 1);
    if (!pool->image.rgb || !pool->image.coverage) {
        reyes_pool_free(pool);
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for a %ux%u image",
                          job->options.width, job->options.height);
    }
    return REYES_OK;
}

void reyes_pool_free(reyes_pool *pool)
{
    reyes_image_free(&pool->image);
    free(pool->renderer);
    free(pool->taken_at);
    free(pool->render_seconds);
    free(pool->turnaround);
    free(pool->done);
    pool->done = NULL;
    pool->renderer = NULL;
    pool->taken_at = pool->render_seconds = pool->turnaround = NULL;
    pthread_mutex_destroy(&pool->lock);
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int reyes_pool_take(reyes_pool *pool, int renderer, unsigned *item)
{
    pthread_mutex_lock(&pool->lock);
    int have = !pool->failed && pool->next < pool->job->items;
    if (have) {
        *item = pool->next++;
        pool->renderer[*item] = renderer;
        pool->taken_at[*item] = now();
    }
    pthread_mutex_unlock(&pool->lock);
    return have;
}

/* Count a delivery and its times, and show it. */
static void delivered(reyes_pool *pool, unsigned item, double seconds)
{
    pthread_mutex_lock(&pool->lock);
    pool->delivered++;
    pool->done[item] = 1;
    pool->turnaround[item] = now() - pool->taken_at[item];
    pool->render_seconds[item] = seconds >= 0.0 ? seconds : pool->turnaround[item];
    int renderer = pool->renderer[item];
    pthread_mutex_unlock(&pool->lock);
    if (pool->progress)
        reyes_progress_item_done(pool->progress, renderer);
}

void reyes_image_pack_rect(const reyes_image *image, const unsigned rect[4], uint8_t *rgb,
                           uint8_t *coverage)
{
    size_t width = rect[2] - rect[0];
    for (unsigned y = rect[1]; y < rect[3]; ++y) {
        size_t from = (size_t)y * image->width + rect[0], row = y - rect[1];
        memcpy(rgb + row * width * 3, image->rgb + from * 3, width * 3);
        memcpy(coverage + row * width, image->coverage + from, width);
    }
}

int reyes_pool_item_rect(const reyes_pool *pool, int64_t item, unsigned rect[4])
{
    const reyes_job *job = pool->job;
    if (item < 0 || item >= (int64_t)job->items)
        return 0;
    if (!job->frames) {
        reyes_job_bucket_rect(job, (unsigned)item, rect);
        return 1;
    }
    rect[0] = rect[1] = 0;
    rect[2] = job->options.width;
    rect[3] = job->options.height;
    return 1;
}

reyes_status reyes_pool_deliver(reyes_pool *pool, unsigned item, const unsigned rect[4],
                                const uint8_t *rgb, const uint8_t *coverage, double seconds,
                                reyes_error *error)
{
    const reyes_job *job = pool->job;
    reyes_status status = REYES_OK;
    unsigned expected[4];
    if (!reyes_pool_item_rect(pool, item, expected))
        return reyes_fail(error, REYES_ERR_RUNTIME, "a result for %s %u, which the job does not have (%u %s)",
                          job->frames ? "frame" : "bucket", job->frames ? item + 1 : item, job->items,
                          job->frames ? "frames" : "buckets");
    if (memcmp(rect, expected, sizeof expected) != 0)
        return reyes_fail(error, REYES_ERR_RUNTIME, "%s %u came with pixels [%u,%u)x[%u,%u), not its "
                          "[%u,%u)x[%u,%u)", job->frames ? "frame" : "bucket", job->frames ? item + 1 : item,
                          rect[0], rect[2], rect[1], rect[3], expected[0], expected[2], expected[1], expected[3]);
    if (job->frames) {
        /* A whole frame: write it (outside the lock; files differ). */
        reyes_image frame = { .width = rect[2] - rect[0], .height = rect[3] - rect[1], .rgb = (uint8_t *)rgb,
                              .coverage = (uint8_t *)coverage };
        char path[4200];
        reyes_job_frame_path(job, item, path, sizeof path);
        reyes_interrupt_outputs_begin(); /* an interrupt waits for the frame and counts it */
        status = reyes_write_png(path, &frame, error);
        if (status == REYES_OK)
            delivered(pool, item, seconds);
        reyes_interrupt_outputs_end(NULL, NULL);
        return status;
    } else {
        /* Tiles are disjoint: no lock needed for the pixels. */
        size_t width = rect[2] - rect[0];
        reyes_image *image = &pool->image;
        for (unsigned y = rect[1]; y < rect[3]; ++y) {
            size_t to = (size_t)y * image->width + rect[0], row = y - rect[1];
            memcpy(image->rgb + to * 3, rgb + row * width * 3, width * 3);
            memcpy(image->coverage + to, coverage + row * width, width);
        }
    }
    if (status == REYES_OK)
        delivered(pool, item, seconds);
    return status;
}

void reyes_pool_describe_written(reyes_pool *pool, char *out, size_t size)
{
    const reyes_job *job = pool->job;
    pthread_mutex_lock(&pool->lock);
    unsigned written = pool->delivered;
    size_t used = 0;
    if (!job->frames || written == 0) {
        snprintf(out, size, "no %s written", job->frames ? "frame" : "image");
    } else {
        used = (size_t)snprintf(out, size, "%u of %u frames written:", written, job->items);
        int ranges = 0;
        for (unsigned f = 0; f < job->items && used < size; ++f) {
            if (!pool->done[f] || (f > 0 && pool->done[f - 1]))
                continue;
            unsigned last = f;
            while (last + 1 < job->items && pool->done[last + 1])
                ++last;
            char first_path[4200], last_path[4200];
            reyes_job_frame_path(job, f, first_path, sizeof first_path);
            reyes_job_frame_path(job, last, last_path, sizeof last_path);
            if (used + strlen(first_path) + strlen(last_path) + 16 >= size) {
                used += (size_t)snprintf(out + used, size - used, " ...");
                break;
            }
            used += (size_t)snprintf(out + used, size - used, "%s %s%s%s", ranges++ ? "," : "", first_path,
                                     last > f ? " to " : "", last > f ? last_path : "");
        }
    }
    pthread_mutex_unlock(&pool->lock);
}

void reyes_pool_fail(reyes_pool *pool, const char *who, reyes_status status, const char *message)
{
    pthread_mutex_lock(&pool->lock);
    if (!pool->failed) {
        pool->failed = 1;
        pool->status = status;
        snprintf(pool->message, sizeof pool->message, "%s: %s", who, message);
    }
    pthread_mutex_unlock(&pool->lock);
}

reyes_status reyes_pool_finish(reyes_pool *pool, reyes_error *error)
{
    pthread_mutex_lock(&pool->lock);
    int failed = pool->failed;
    unsigned delivered = pool->delivered, items = pool->job->items;
    pthread_mutex_unlock(&pool->lock);
    if (failed)
        return reyes_fail(error, pool->status, "%s", pool->message);
    if (delivered != items)
        return reyes_fail(error, REYES_ERR_RUNTIME, "%u of %u %s were delivered", delivered, items,
                          pool->job->frames ? "frames" : "buckets");
    return REYES_OK;
}

/* The bucket source of a renderer on the pool's own process. */
static int source_next(void *user, unsigned *item)
{
    reyes_pool_client *client = user;
    return reyes_pool_take(client->pool, client->renderer, item);
}

static reyes_status source_done(void *user, unsigned item, const reyes_image *image, unsigned x0,
                                unsigned y0, unsigned x1, unsigned y1, reyes_error *error)
{
    reyes_pool *pool = ((reyes_pool_client *)user)->pool;
    if (pool->job->frames) {
        const unsigned rect[4] = { 0, 0, image->width, image->height };
        return reyes_pool_deliver(pool, item, rect, image->rgb, image->coverage, -1.0, error);
    }
    /* Straight from the renderer's image into the pool's. */
    reyes_image_copy_rect(&pool->image, image, x0, y0, x1, y1);
    delivered(pool, item, -1.0);
    return REYES_OK;
}

reyes_bucket_source reyes_pool_source(reyes_pool_client *client)
{
    return (reyes_bucket_source){ source_next, source_done, client };
}

void reyes_farm_worker_init(reyes_farm_worker *w, reyes_pool *pool, int renderer,
                            const perma_device_ref *device, const char *who)
{
    memset(w, 0, sizeof *w);
    w->client = (reyes_pool_client){ pool, renderer };
    w->device = *device;
    perma_device_ref_format(device, w->report.device, sizeof w->report.device);
    snprintf(w->who, sizeof w->who, "%s%s", who ? who : "device ", who ? "" : w->report.device);
}

void *reyes_farm_worker_run(void *worker)
{
    reyes_farm_worker *w = worker;
    reyes_pool *pool = w->client.pool;
    reyes_options options = pool->job->options;
    options.device = &w->device;
    if (pool->progress) {
        w->slot = (reyes_progress_slot){ pool->progress, (unsigned)w->client.renderer };
        options.progress = reyes_progress_runtime;
        options.progress_user = &w->slot;
        options.progress_interval = REYES_PROGRESS_INTERVAL;
    }
    reyes_renderer *renderer = NULL;
    reyes_error error;
    double start = now();
    reyes_status status = reyes_renderer_create(&options, &renderer, &error);
    w->report.create_seconds = now() - start;
    if (status == REYES_OK) {
        snprintf(w->report.summary, sizeof w->report.summary, "%s", reyes_renderer_device(renderer));
        reyes_bucket_source source = reyes_pool_source(&w->client);
        status = reyes_job_work(pool->job, renderer, &source, &w->report, &error);
    }
    if (status != REYES_OK)
        reyes_pool_fail(pool, w->who, status, error.message);
    reyes_renderer_destroy(renderer);
    w->finished = 1;
    return NULL;
}

reyes_status reyes_farm_start(reyes_pool *pool, const perma_device_ref *devices, unsigned count,
                              reyes_farm_worker *workers, reyes_error *error)
{
    for (unsigned k = 0; k < count; ++k)
        reyes_farm_worker_init(&workers[k], pool, (int)k, &devices[k], NULL);
    for (unsigned k = 0; k < count; ++k) {
        if (pthread_create(&workers[k].thread, NULL, reyes_farm_worker_run, &workers[k]) != 0) {
            reyes_pool_fail(pool, "farm", REYES_ERR_NO_MEMORY, "cannot start a render thread");
            reyes_farm_join(workers, k);
            return reyes_fail(error, REYES_ERR_NO_MEMORY, "cannot start a render thread for device %s",
                              workers[k].report.device);
        }
        workers[k].started = 1;
    }
    return REYES_OK;
}

void reyes_farm_join(reyes_farm_worker *workers, unsigned count)
{
    for (unsigned k = 0; k < count; ++k) {
        if (workers[k].started)
            pthread_join(workers[k].thread, NULL);
        workers[k].started = 0;
    }
}

reyes_status reyes_farm_run(reyes_pool *pool, const perma_device_ref *devices, unsigned count,
                            reyes_farm_worker *workers, reyes_error *error)
{
    reyes_status status = reyes_farm_start(pool, devices, count, workers, error);
    if (status != REYES_OK)
        return status;
    reyes_farm_join(workers, count);
    return reyes_pool_finish(pool, error);
}
