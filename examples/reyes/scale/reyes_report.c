/* Summaries of scale-out renders (reyes_report.h). */
#include <inttypes.h>
#include <string.h>

#include "reyes_report.h"

void reyes_report_print(FILE *out, const reyes_job *job, const reyes_work_report *reports,
                        unsigned count, const char *where, double seconds)
{
    const char *kind = job->frames ? "frames" : "buckets";
    uint64_t grids = 0, micropolygons = 0;
    for (unsigned k = 0; k < count; ++k) {
        grids += reports[k].grids;
        micropolygons += reports[k].micropolygons;
    }
    if (job->frames) {
        char first[4200], last[4200];
        reyes_job_frame_path(job, 0, first, sizeof first);
        reyes_job_frame_path(job, job->frames - 1, last, sizeof last);
        fprintf(out, "%s .. %s: %u frames of ", first, last, job->frames);
    } else {
        fprintf(out, "%s: ", job->output);
    }
    fprintf(out, "%ux%u, %zu patches, %u %s on %u %s%s, %" PRIu64 " grids, %" PRIu64
                 " micropolygons, %.3f s\n",
            job->options.width, job->options.height, job->scene.patch_count, job->items, kind, count,
            where, count == 1 ? "" : "s", grids, micropolygons, seconds);
    for (unsigned k = 0; k < count; ++k) {
        const reyes_work_report *r = &reports[k];
        char rank[32] = "";
        if (strcmp(where, "rank") == 0)
            snprintf(rank, sizeof rank, "rank %d, ", r->rank);
        if (strcmp(r->device, "none") == 0)
            fprintf(out, "  %scoordinator: handed out and gathered\n", rank);
        else
            fprintf(out, "  %sdevice %s: %u %s in %.3f s (%s)\n", rank, r->device, r->items, kind,
                    r->seconds, r->summary);
    }
}

static void json_string(FILE *out, const char *s)
{
    fputc('"', out);
    for (; *s; ++s) {
        if (*s == '"' || *s == '\\')
            fprintf(out, "\\%c", *s);
        else if ((unsigned char)*s < 0x20)
            fprintf(out, "\\u%04x", *s);
        else
            fputc(*s, out);
    }
    fputc('"', out);
}

static void json_numbers(FILE *out, const char *name, const double *values, const int *ints, unsigned count)
{
    fprintf(out, ",\n  \"%s\": [", name);
    for (unsigned k = 0; k < count; ++k) {
        if (values)
            fprintf(out, "%s%.6f", k ? ", " : "", values[k]);
        else
            fprintf(out, "%s%d", k ? ", " : "", ints[k]);
    }
    fprintf(out, "]");
}

typedef struct report_output {
    const reyes_pool *pool;
    const reyes_work_report *reports;
    unsigned count;
    double seconds;
} report_output;

static reyes_status write_json(FILE *out, const void *data, reyes_error *error)
{
    const report_output *o = data;
    const reyes_pool *pool = o->pool;
    const reyes_job *job = pool->job;
    fprintf(out, "{\n  \"width\": %u, \"height\": %u, \"patches_in\": %zu,\n", job->options.width,
            job->options.height, job->scene.patch_count);
    fprintf(out, "  \"bucket_width\": %u, \"bucket_height\": %u, \"frames\": %u, \"items\": %u,\n",
            job->options.bucket_width, job->options.bucket_height, job->frames, job->items);
    fprintf(out, "  \"seconds\": %.6f,\n  \"renderers\": [\n", o->seconds);
    for (unsigned k = 0; k < o->count; ++k) {
        const reyes_work_report *r = &o->reports[k];
        fprintf(out, "    {\"rank\": %d, \"device\": ", r->rank);
        json_string(out, r->device);
        fprintf(out, ", \"summary\": ");
        json_string(out, r->summary);
        fprintf(out, ", \"items\": %u, \"seconds\": %.6f, \"create_seconds\": %.6f, \"first_seconds\": %.6f, "
                     "\"grids\": %" PRIu64 ", \"micropolygons\": %" PRIu64 ", \"samples_written\": %" PRIu64 "}%s\n",
                r->items, r->seconds, r->create_seconds, r->first_seconds, r->grids, r->micropolygons,
                r->samples_written, k + 1 < o->count ? "," : "");
    }
    fprintf(out, "  ]");
    json_numbers(out, "item_renderer", NULL, pool->renderer, job->items);
    json_numbers(out, "item_seconds", pool->render_seconds, NULL, job->items);
    json_numbers(out, "item_turnaround", pool->turnaround, NULL, job->items);
    fprintf(out, "\n}\n");
    (void)error; /* a failed write is reported by the output file */
    return REYES_OK;
}

reyes_status reyes_report_write_outputs(const reyes_pool *pool, const reyes_work_report *reports, unsigned count,
                                        double seconds, const char *stats_path, reyes_error *error)
{
    const report_output report = { pool, reports, count, seconds };
    reyes_output_file files[2];
    size_t n = 0;
    if (!pool->job->frames)
        files[n++] = (reyes_output_file){ pool->job->output, reyes_png_writer, &pool->image };
    if (stats_path)
        files[n++] = (reyes_output_file){ stats_path, write_json, &report };
    reyes_status status = reyes_write_outputs(files, n, error);
    if (status != REYES_OK && pool->job->frames && error) {
        /* The frames were written as they came: say so. */
        char first[4200], last[4200];
        reyes_job_frame_path(pool->job, 0, first, sizeof first);
        reyes_job_frame_path(pool->job, pool->job->frames - 1, last, sizeof last);
        size_t used = strlen(error->message);
        snprintf(error->message + used, sizeof error->message - used, "; the %u frames %s .. %s were written",
                 pool->job->frames, first, last);
    }
    return status;
}
