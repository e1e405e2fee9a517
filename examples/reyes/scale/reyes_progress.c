/* reyes-render's progress line (reyes_progress.h). */
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "reyes_progress.h"

#define TERMINAL_SECONDS 0.1 /* redraws on a terminal at most this often */
#define LINE_SECONDS 2.0     /* lines elsewhere at most this often */

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* "3.2 s", "4m05s", "2h07m" */
static void duration(char *out, size_t size, double seconds)
{
    if (seconds < 60.0)
        snprintf(out, size, "%.1f s", seconds);
    else if (seconds < 3600.0)
        snprintf(out, size, "%dm%02ds", (int)(seconds / 60.0), (int)seconds % 60);
    else
        snprintf(out, size, "%dh%02dm", (int)(seconds / 3600.0), (int)(seconds / 60.0) % 60);
}

void reyes_progress_format(char *out, size_t size, unsigned done, unsigned total, const char *unit, double share,
                           double elapsed, int finished)
{
    char spent[32], left[32];
    duration(spent, sizeof spent, elapsed);
    int used = snprintf(out, size, "%u/%u %s, %.1f%%, %s elapsed", done, total, unit, 100.0 * share, spent);
    if (!finished && share > 0.0 && share < 1.0 && used > 0 && (size_t)used < size) {
        duration(left, sizeof left, elapsed * (1.0 - share) / share);
        snprintf(out + used, size - (size_t)used, ", about %s left", left);
    }
}

/* The share of the job done: items done and the current items' shares. */
static double job_share(const reyes_progress *p)
{
    if (p->total == 0)
        return 1.0;
    double items = p->done;
    for (unsigned r = 0; r < REYES_PROGRESS_RENDERERS; ++r)
        items += p->share[r];
    double share = items / p->total;
    return share < 1.0 ? share : 1.0;
}

/* Draw the line now (p->lock held). */
static void draw(reyes_progress *p, double t, int finished)
{
    char line[256];
    reyes_progress_format(line, sizeof line, p->done, p->total, p->unit, finished ? 1.0 : job_share(p),
                          t - p->start, finished);
    if (p->terminal)
        fprintf(p->out, "\r%s: %s\033[K%s", p->program, line, finished ? "\n" : "");
    else
        fprintf(p->out, "%s: %s\n", p->program, line);
    fflush(p->out);
    p->drawn = p->terminal && !finished;
    p->drawn_at = t;
}

/* Draw unless the last line is too recent (p->lock held). */
static void maybe_draw(reyes_progress *p)
{
    double t = now();
    if (t - p->drawn_at >= (p->terminal ? TERMINAL_SECONDS : LINE_SECONDS))
        draw(p, t, 0);
}

int reyes_progress_wanted(int forced, int quiet, int *terminal)
{
    *terminal = isatty(STDERR_FILENO);
    return !quiet && (forced || *terminal);
}

void reyes_progress_start(reyes_progress *p, FILE *out, int terminal, const char *program, const char *unit,
                          unsigned total)
{
    memset(p, 0, sizeof *p);
    pthread_mutex_init(&p->lock, NULL);
    p->out = out;
    p->terminal = terminal;
    const char *slash = strrchr(program, '/');
    p->program = slash ? slash + 1 : program; /* short: the line must not wrap */
    p->unit = unit;
    p->total = total;
    p->start = now();
    pthread_mutex_lock(&p->lock);
    draw(p, p->start, 0);
    pthread_mutex_unlock(&p->lock);
}

void reyes_progress_item_done(reyes_progress *p, int renderer)
{
    pthread_mutex_lock(&p->lock);
    if (p->done < p->total)
        p->done++;
    if (renderer >= 0 && renderer < REYES_PROGRESS_RENDERERS)
        p->share[renderer] = 0.0;
    maybe_draw(p);
    pthread_mutex_unlock(&p->lock);
}

/* The share of an item a run of the Reyes procedures has done, once it is
 * known: the items of the procedures that make pixels (dice, rasterize,
 * stitch) completed, of those completed or queued, when no subdivision
 * (bound, split) is left to find more; -1 while some is (an estimate
 * would jump back), and for a run without pixel work (the stitching plan,
 * which only subdivides). */
static double run_share(const perma_progress *progress)
{
    static const char *const subdividing[] = { "bound", "split_u", "split_v" };
    uint64_t done = 0, all = 0;
    for (unsigned q = 0; q < progress->procedure_count; ++q) {
        const perma_procedure_progress *pp = &progress->procedures[q];
        int subdivides = 0;
        for (size_t k = 0; k < sizeof subdividing / sizeof subdividing[0]; ++k)
            subdivides |= strcmp(pp->name, subdividing[k]) == 0;
        if (subdivides && pp->queued)
            return -1.0;
        if (!subdivides) {
            done += pp->completed;
            all += pp->completed + pp->queued;
        }
    }
    return all ? (double)done / (double)all : -1.0;
}

void reyes_progress_runtime(void *user, const perma_progress *progress)
{
    reyes_progress_slot *slot = user;
    reyes_progress *p = slot->progress;
    double share = run_share(progress);
    pthread_mutex_lock(&p->lock);
    double *current = &p->share[slot->renderer % REYES_PROGRESS_RENDERERS];
    /* Never back within an item, and short of a whole one. */
    if (share > *current)
        *current = share < 0.99 ? share : 0.99;
    maybe_draw(p);
    pthread_mutex_unlock(&p->lock);
}

void reyes_progress_finish(reyes_progress *p, int succeeded)
{
    pthread_mutex_lock(&p->lock);
    if (succeeded)
        draw(p, now(), 1);
    else if (p->drawn)
        fputc('\n', p->out);
    p->drawn = 0;
    fflush(p->out);
    pthread_mutex_unlock(&p->lock);
}

void reyes_progress_free(reyes_progress *p)
{
    pthread_mutex_destroy(&p->lock);
}
