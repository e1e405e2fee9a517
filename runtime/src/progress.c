/* A run's progress (perma_get_progress, config.progress).
 *
 * While a kernel runs, each group's record on the watch page
 * (kernels/perma_abi.h) counts the items it completed per procedure and
 * the items it emitted into each procedure: 32-bit words that only grow
 * (and wrap).  The watchdog's loop, which wakes at least every 50 ms,
 * samples them (perma_progress_sample): the difference to the last sample
 * of each word is added to 64-bit counts of the launch, so a wrap is never
 * lost.  After each launch the counts are set from the statistics, which
 * are exact.  Readers on other threads copy a published snapshot under a
 * mutex; only perma_run's thread writes the counts.
 *
 * Nothing is sampled until progress is wanted (a callback configured, or
 * perma_get_progress called once), so a runtime whose progress nobody
 * reads pays only the kernel's stores. */
#include "clock.h"
#include "internal.h"
#include "progress.h"
#include "state.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

/* config.progress_interval when 0. */
#define DEFAULT_INTERVAL 0.5

struct perma_progress_state {
    pthread_mutex_t lock;   /* guards `shown` and `start` */
    perma_progress shown;   /* what readers get */
    double start;           /* host time of the run's start */
    bool stopped;           /* the run's clock stopped: shown.elapsed is final */
    int wanted;             /* set by any thread (atomic): someone reads the progress */
    /* perma_run's thread only. */
    uint64_t seeded[PERMA_MAX_PROCEDURES];
    uint64_t completed[PERMA_MAX_PROCEDURES]; /* as of the last launch's end (exact) */
    uint64_t into[PERMA_MAX_PROCEDURES];      /* items emitted into each procedure, likewise */
    uint64_t launch_completed[PERMA_MAX_PROCEDURES], launch_into[PERMA_MAX_PROCEDURES];
    uint32_t *last;         /* the count words as last sampled: per group, 2 * procedures */
    size_t last_words;      /* words `last` holds */
    bool sampling;          /* `last` is valid for the launch in flight */
    double last_callback;
};

perma_status perma_progress_open(perma_runtime *rt)
{
    perma_progress_state *p = calloc(1, sizeof *p);
    if (!p || pthread_mutex_init(&p->lock, NULL) != 0) {
        free(p);
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for the progress");
    }
    p->wanted = rt->config.progress != NULL;
    p->shown.live = rt->caps.watch_visible;
    rt->progress = p;
    return PERMA_OK;
}

void perma_progress_close(perma_runtime *rt)
{
    perma_progress_state *p = rt->progress;
    if (!p)
        return;
    pthread_mutex_destroy(&p->lock);
    free(p->last);
    free(p);
    rt->progress = NULL;
}

/* Publish the counts (the last launches' plus the launch in flight's). */
static void publish(perma_runtime *rt, double now)
{
    perma_progress_state *p = rt->progress;
    pthread_mutex_lock(&p->lock);
    perma_progress *s = &p->shown;
    s->elapsed = s->running && !p->stopped ? now - p->start : s->elapsed;
    s->completed = s->queued = 0;
    s->procedure_count = rt->proc_count;
    for (unsigned q = 0; q < rt->proc_count; ++q) {
        uint64_t completed = p->completed[q] + p->launch_completed[q];
        uint64_t arrived = p->seeded[q] + p->into[q] + p->launch_into[q];
        /* While a kernel runs a group may count an item done before its
         * producer's group counts it emitted: never below zero. */
        uint64_t queued = arrived > completed ? arrived - completed : 0;
        s->procedures[q].name = rt->procs[q].name;
        s->procedures[q].completed = completed;
        s->procedures[q].queued = queued;
        s->completed += completed;
        s->queued += queued;
    }
    pthread_mutex_unlock(&p->lock);
}

static void call_back(perma_runtime *rt, double now)
{
    perma_progress_state *p = rt->progress;
    if (!rt->config.progress)
        return;
    perma_progress copy;
    pthread_mutex_lock(&p->lock);
    copy = p->shown;
    pthread_mutex_unlock(&p->lock);
    p->last_callback = now;
    rt->config.progress(rt->config.progress_user, &copy);
}

static double interval(const perma_runtime *rt)
{
    return rt->config.progress_interval > 0 ? rt->config.progress_interval : DEFAULT_INTERVAL;
}

void perma_progress_run_begins(perma_runtime *rt, double start)
{
    perma_progress_state *p = rt->progress;
    for (unsigned q = 0; q < rt->proc_count; ++q) {
        p->seeded[q] = rt->procs[q].stats.seeded;
        p->completed[q] = p->into[q] = p->launch_completed[q] = p->launch_into[q] = 0;
    }
    p->sampling = false;
    pthread_mutex_lock(&p->lock);
    unsigned run = p->shown.run;
    memset(&p->shown, 0, sizeof p->shown);
    p->shown.run = run + 1;
    p->shown.running = 1;
    p->shown.live = rt->caps.watch_visible;
    p->start = start;
    p->stopped = false;
    pthread_mutex_unlock(&p->lock);
    publish(rt, start);
    call_back(rt, start);
}

void perma_progress_launch_begins(perma_runtime *rt)
{
    perma_progress_state *p = rt->progress;
    memset(p->launch_completed, 0, sizeof p->launch_completed);
    memset(p->launch_into, 0, sizeof p->launch_into);
    /* The page was just cleared: every word starts at 0. */
    size_t words = (size_t)rt->work_groups * 2 * rt->proc_count;
    if (words > p->last_words) {
        uint32_t *last = realloc(p->last, words * sizeof *last);
        if (!last) {
            p->sampling = false; /* this launch moves the counts only at its end */
            return;
        }
        p->last = last;
        p->last_words = words;
    }
    memset(p->last, 0, words * sizeof *p->last);
    p->sampling = true;
}

void perma_progress_kernel_started(perma_runtime *rt)
{
    perma_progress_state *p = rt->progress;
    pthread_mutex_lock(&p->lock);
    p->shown.launches++;
    pthread_mutex_unlock(&p->lock);
}

void perma_progress_sample(perma_runtime *rt, double now)
{
    perma_progress_state *p = rt->progress;
    if (!p->sampling || !__atomic_load_n(&p->wanted, __ATOMIC_RELAXED))
        return;
    unsigned procs = rt->proc_count;
    for (unsigned g = 0; g < rt->work_groups; ++g) {
        const uint32_t *counts = perma_state_watch_record(rt, g) + PERMA_WATCH_COUNTS;
        uint32_t *last = p->last + (size_t)g * 2 * procs;
        for (unsigned w = 0; w < 2 * procs; ++w) {
            uint32_t now_word = __atomic_load_n(counts + w, __ATOMIC_RELAXED);
            uint32_t delta = now_word - last[w]; /* modulo 2^32: a wrap is a small step */
            last[w] = now_word;
            if (w < procs)
                p->launch_completed[w] += delta;
            else
                p->launch_into[w - procs] += delta;
        }
    }
    publish(rt, now);
    if (now - p->last_callback >= interval(rt))
        call_back(rt, now);
}

void perma_progress_launch_ends(perma_runtime *rt)
{
    perma_progress_state *p = rt->progress;
    memset(p->into, 0, sizeof p->into);
    for (unsigned q = 0; q < rt->proc_count; ++q) {
        const perma_proc_info *info = &rt->procs[q];
        p->completed[q] = info->stats.items;
        for (unsigned e = 0; e < info->emit_count; ++e)
            p->into[info->emit_target[e]] += info->stats.emitted[e];
    }
    memset(p->launch_completed, 0, sizeof p->launch_completed);
    memset(p->launch_into, 0, sizeof p->launch_into);
    p->sampling = false;
    pthread_mutex_lock(&p->lock);
    p->shown.launches = rt->stats.launches;
    pthread_mutex_unlock(&p->lock);
    publish(rt, perma_now());
}

double perma_progress_stop_clock(perma_runtime *rt)
{
    perma_progress_state *p = rt->progress;
    pthread_mutex_lock(&p->lock);
    double seconds = perma_now() - p->start;
    p->shown.elapsed = seconds;
    p->stopped = true; /* no reader sees more from now on */
    pthread_mutex_unlock(&p->lock);
    return seconds;
}

void perma_progress_run_ends(perma_runtime *rt)
{
    perma_progress_state *p = rt->progress;
    p->sampling = false;
    publish(rt, perma_now());
    pthread_mutex_lock(&p->lock);
    p->shown.running = 0;
    pthread_mutex_unlock(&p->lock);
    call_back(rt, perma_now());
}

perma_status perma_get_progress(perma_runtime *rt, perma_progress *out)
{
    if (!rt || !out || !rt->progress)
        return PERMA_ERR_ARGUMENT;
    perma_progress_state *p = rt->progress;
    __atomic_store_n(&p->wanted, 1, __ATOMIC_RELAXED);
    pthread_mutex_lock(&p->lock);
    *out = p->shown;
    if (out->running && !p->stopped)
        out->elapsed = perma_now() - p->start;
    pthread_mutex_unlock(&p->lock);
    return PERMA_OK;
}
