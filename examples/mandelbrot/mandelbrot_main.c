/* mandelbrot: render an adaptive Mandelbrot image with perma, or --compare. */
#include <stdlib.h>

#include "mandel_options.h"

static int render(const mandel_options *o, const mandel_params *p, char *message, size_t size)
{
    uint32_t *counts = malloc((size_t)p->width * p->height * sizeof *counts);
    if (!counts) {
        snprintf(message, size, "perma-mandelbrot: out of memory for %ux%u pixels", p->width, p->height);
        return MANDEL_ERR_RUNTIME;
    }
    mandel_status st = MANDEL_OK;
    if (o->reference) {
        mandel_brute_force(p, counts);
    } else {
        mandel_run run = { *p, counts, 0 };
        st = example_session_once(&mandel_program, &run, &o->common.run, stdout, o->common.stats, message, size)
                 ? MANDEL_ERR_RUNTIME
                 : MANDEL_OK;
    }
    if (st == MANDEL_OK)
        st = mandel_write_png(o->output, p, counts, message, size);
    if (st == MANDEL_OK)
        printf("wrote %s (%ux%u, max_iter %u)\n", o->output, p->width, p->height, p->max_iter);
    free(counts);
    return st;
}

int main(int argc, char **argv)
{
    char message[PERMA_MESSAGE_MAX + 128] = "";
    mandel_options o;
    perma_cli_status parsed = mandel_parse_options(argc, argv, &o, message, sizeof message);
    if (parsed != PERMA_CLI_OK)
        return perma_cli_exit_status(parsed);
    mandel_params p;
    mandel_params_init(&p, o.size[0], o.size[1], o.region[0], o.region[1], o.region[2], o.region[3],
                       o.max_iter, o.min_size);
    int st = o.common.compare ? (int)mandel_compare(&p, o.common.run.work_groups, o.common.repeats, stdout,
                                                    message, sizeof message)
                              : render(&o, &p, message, sizeof message);
    if (st != MANDEL_OK)
        fprintf(stderr, "%s\n", message);
    return st;
}
