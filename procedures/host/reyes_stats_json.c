/* Statistics of a render as JSON. */
#include <inttypes.h>
#include <string.h>

#include "reyes.h"

/* `text` as a JSON string. */
static void json_string(FILE *out, const char *text)
{
    fputc('"', out);
    for (const unsigned char *c = (const unsigned char *)text; *c; ++c) {
        if (*c == '"' || *c == '\\')
            fprintf(out, "\\%c", *c);
        else if (*c < 0x20)
            fprintf(out, "\\u%04x", *c);
        else
            fputc(*c, out);
    }
    fputc('"', out);
}

static void write_procedure(FILE *out, const perma_procedure_stats *p, int last)
{
    fprintf(out, "    \"%s\": {\"items\": %" PRIu64 ", \"batches\": %" PRIu64
                 ", \"seeded\": %" PRIu64 ", \"emitted\": [",
            p->name ? p->name : "?", p->items, p->batches, p->seeded);
    for (unsigned e = 0; e < p->emit_count && e < PERMA_MAX_EMITS; ++e)
        fprintf(out, "%s%" PRIu64, e ? ", " : "", p->emitted[e]);
    fprintf(out, "], \"peak_queue_items\": %" PRIu64 ", \"queue_capacity\": %zu, \"regrowths\": %u}%s\n",
            p->peak_queue_items, p->queue_capacity, p->regrowths, last ? "" : ",");
}

static const char *name_or_unknown(const char *name)
{
    return name ? name : "?";
}

/* Bucket size (0 x 0: none), count, and the peak queue memory of each
 * bucket (row by row) and their maximum. */
static void write_buckets(FILE *out, const reyes_stats *s, const reyes_options *o)
{
    size_t count = (size_t)s->bucket_columns * s->bucket_rows;
    fprintf(out, "  \"bucket_width\": %u, \"bucket_height\": %u, \"buckets\": %zu,\n",
            o->bucket_width, o->bucket_height, count);
    fprintf(out, "  \"bucket_peak_queue_bytes_max\": %zu,\n", s->peak_queue_bytes);
    fprintf(out, "  \"bucket_peak_queue_bytes\": [");
    if (s->bucket_peak_queue_bytes) {
        for (size_t k = 0; k < count; ++k)
            fprintf(out, "%s%zu", k ? ", " : "", s->bucket_peak_queue_bytes[k]);
    } else {
        fprintf(out, "%zu", s->peak_queue_bytes);
    }
    fprintf(out, "],\n");
}

/* The micropolygons' areas in square pixels (with area_stats, else
 * null): mean, percentiles and the bins' counts. */
static void write_areas(FILE *out, const reyes_stats *s, const reyes_options *o)
{
    if (!o->area_stats) {
        fprintf(out, "  \"micropolygon_area\": null,\n");
        return;
    }
    fprintf(out, "  \"micropolygon_area\": {\"mean\": %.6g, \"p10\": %.6g, \"p25\": %.6g, \"p50\": %.6g, "
                 "\"p75\": %.6g, \"p90\": %.6g, \"p99\": %.6g, \"bins\": [",
            reyes_stats_area_mean(s), reyes_stats_area_percentile(s, 0.10), reyes_stats_area_percentile(s, 0.25),
            reyes_stats_area_percentile(s, 0.50), reyes_stats_area_percentile(s, 0.75),
            reyes_stats_area_percentile(s, 0.90), reyes_stats_area_percentile(s, 0.99));
    for (unsigned b = 0; b < REYES_AREA_BINS; ++b)
        fprintf(out, "%s%" PRIu64, b ? ", " : "", s->micropolygon_area_bins[b]);
    fprintf(out, "]},\n");
}

reyes_status reyes_write_stats_json(FILE *out, const reyes_stats *s, const reyes_options *o,
                                    reyes_error *error)
{
    fprintf(out, "{\n");
    fprintf(out, "  \"width\": %u, \"height\": %u, \"bound_px\": %g, \"grid\": %u, \"spp\": %u, "
                 "\"max_depth\": %u,\n",
            o->width, o->height, (double)o->bound_px, o->grid, o->spp, o->max_depth);
    fprintf(out, "  \"patches_in\": %" PRIu64 ",\n", s->patches_in);
    fprintf(out, "  \"subdivision\": \"%s\", \"epsilon\": %g, \"lambda\": %g, "
                 "\"tiered_bound_px\": %g,\n",
            o->subdivision == REYES_SUBDIVISION_TIERED ? "tiered" : "bound",
            (double)o->flat_epsilon, (double)o->flat_lambda,
            (double)(o->flat_bound_px > 0.0f ? o->flat_bound_px : (float)(o->grid - 1)));
    fprintf(out, "  \"splits\": %" PRIu64 ",\n", s->splits);
    fprintf(out, "  \"split_reasons\": {\"bound\": %" PRIu64 ", \"edge\": %" PRIu64
                 ", \"inner\": %" PRIu64 ", \"near\": %" PRIu64 "},\n",
            s->split_bound, s->split_edge, s->split_inner, s->split_near);
    fprintf(out, "  \"culled\": %" PRIu64 ",\n", s->culled);
    fprintf(out, "  \"grids\": %" PRIu64 ",\n", s->grids);
    fprintf(out, "  \"occlusion\": \"%s\", \"occluded\": %" PRIu64 ",\n", o->occlusion_cull ? "on" : "off",
            s->occluded);
    fprintf(out, "  \"forced_dice\": %" PRIu64 ",\n", s->forced_dice);
    fprintf(out, "  \"micropolygons\": %" PRIu64 ",\n", s->micropolygons);
    write_areas(out, s, o);
    fprintf(out, "  \"grid\": %u, \"shading_rate\": %g,\n", o->grid, (double)o->shading_rate);
    fprintf(out, "  \"samples_written\": %" PRIu64 ",\n", s->samples_written);
    fprintf(out, "  \"crack_fix\": \"%s\", \"stitches\": %" PRIu64 ", \"fillers\": %" PRIu64 ",\n",
            o->crack_fix == REYES_CRACK_FIX_STITCH  ? "stitch"
            : o->crack_fix == REYES_CRACK_FIX_WEDGE    ? "wedge"
            : o->crack_fix == REYES_CRACK_FIX_POLYLINE ? "polyline"
                                                        : "none",
            s->stitches, s->fillers);
    fprintf(out, "  \"peak_queue_bytes\": %zu,\n", s->peak_queue_bytes);
    fprintf(out, "  \"displace_mode\": %u, \"displace_amplitude\": %g, \"motion\": [%g, %g, %g], "
                 "\"aperture\": %g, \"focus\": %g, \"time_samples\": %u,\n",
            o->displace_mode, (double)o->displace_amplitude, (double)o->motion[0],
            (double)o->motion[1], (double)o->motion[2], (double)o->aperture, (double)o->focus,
            o->time_samples);
    fprintf(out, "  \"motion_axis\": [%g, %g, %g], \"motion_angle_deg\": %g,\n", (double)o->motion_axis[0],
            (double)o->motion_axis[1], (double)o->motion_axis[2], (double)o->motion_angle_deg);
    fprintf(out, "  \"blur_algo\": \"%s\", \"blur_tile\": %u, \"blur_permutations\": %u,\n",
            name_or_unknown(reyes_blur_algo_name(o->blur_algo)), o->blur_tile, o->blur_permutations);
    write_buckets(out, s, o);
    fprintf(out, "  \"seconds\": %.6f,\n", s->seconds);
    fprintf(out, "  \"work_groups\": %u, \"group_size\": %u, \"launches\": %u, \"regrowths\": %u,\n",
            s->run.work_groups, s->run.group_size, s->run.launches, s->run.regrowths);
    fprintf(out, "  \"work_groups_reason\": ");
    json_string(out, s->work_groups_reason);
    fprintf(out, ", \"resident_groups\": %u, \"kernel_local_bytes\": %zu,\n", s->run.resident_groups,
            s->run.kernel_local_bytes);
    fprintf(out, "  \"technique\": \"%s\", \"strategy\": \"%s\", \"victim\": \"%s\", "
                 "\"local_queue_items\": %u, \"batch_limit\": %u,\n",
            name_or_unknown(perma_technique_name(o->schedule.technique)),
            name_or_unknown(perma_strategy_name(o->schedule.strategy)),
            name_or_unknown(perma_victim_name(o->schedule.victim)), o->schedule.local_queue_items,
            o->schedule.batch_limit);
    fprintf(out, "  \"steals\": %" PRIu64 ", \"donations\": %" PRIu64 ", \"spills\": %" PRIu64 ",\n",
            s->run.steals, s->run.donations, s->run.spills);
    fprintf(out, "  \"stack_items\": %u, \"stacked_items\": %" PRIu64 ", \"stack_spills\": %" PRIu64
                 ", \"stack_peak\": %u,\n",
            s->run.stack_items, s->run.stacked_items, s->run.stack_spills, s->run.stack_peak);
    fprintf(out, "  \"procedures\": {\n");
    for (int p = 0; p < REYES_PROC_COUNT; ++p)
        write_procedure(out, &s->procedures[p], p == REYES_PROC_COUNT - 1);
    fprintf(out, "  }\n}\n");
    if (ferror(out))
        return reyes_fail(error, REYES_ERR_IO, "writing the statistics failed");
    return REYES_OK;
}

reyes_status reyes_stats_writer(FILE *out, const void *data, reyes_error *error)
{
    const reyes_stats_output *s = data;
    return reyes_write_stats_json(out, s->stats, s->options, error);
}

reyes_status reyes_save_stats_json(const char *path, const reyes_stats *stats,
                                   const reyes_options *options, reyes_error *error)
{
    const reyes_stats_output data = { stats, options };
    const reyes_output_file file = { path, reyes_stats_writer, &data };
    return reyes_write_outputs(&file, 1, error);
}
