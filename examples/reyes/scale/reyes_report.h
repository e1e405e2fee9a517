/* What a scale-out render prints and writes (--stats): the image or
 * frames, then one line (one JSON object) per renderer. */
#ifndef REYES_REPORT_H
#define REYES_REPORT_H

#include <stdio.h>

#include "reyes_farm.h"

/* "out.png: 512x512, 38 patches, 64 buckets on 2 devices, ..." and a line
 * per renderer; `where` is "device" or "rank". */
void reyes_report_print(FILE *out, const reyes_job *job, const reyes_work_report *reports,
                        unsigned count, const char *where, double seconds);

/* Write the image (not for frames, which are written as they arrive) and,
 * with stats_path, the statistics together (reyes_write_outputs): both or
 * neither.  The statistics: {"width": ..., "items": ..., "seconds": ...,
 * "renderers": [{...}, ...], "item_renderer": [...], "item_seconds":
 * [...], "item_turnaround": [...]} (per item: the index of its renderer in
 * "renderers", the renderer's seconds for it, the seconds from handing
 * out to delivery). */
reyes_status reyes_report_write_outputs(const reyes_pool *pool, const reyes_work_report *reports, unsigned count,
                                        double seconds, const char *stats_path, reyes_error *error);

#endif
