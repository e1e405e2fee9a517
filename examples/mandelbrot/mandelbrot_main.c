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
        mandel_session *s;
        st = mandel_session_create(p, &o->run, counts, &s, message, size);
        if (st == MANDEL_OK) {
            printf("device: %s\n", perma_device_summary(mandel_session_runtime(s)));
            st = mandel_session_run(s, message, size);
            if (st == MANDEL_OK && o->stats)
                perma_print_stats(mandel_session_runtime(s), stdout);
            mandel_session_destroy(s);
        }
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
    mandel_status st = mandel_parse_options(argc, argv, &o, message, sizeof message);
    if (st != MANDEL_OK) {
        fprintf(stderr, "%s\n", message);
        return st;
    }
    if (o.help) {
        mandel_print_usage(stdout);
        return 0;
    }
    if (o.version) {
        printf("perma-mandelbrot %s\n", PERMA_VERSION_STRING);
        return 0;
    }
    mandel_params p;
    mandel_params_init(&p, o.width, o.height, o.region[0], o.region[1], o.region[2], o.region[3],
                       o.max_iter, o.min_size);
    if (o.compare)
        st = mandel_compare(&p, o.run.work_groups, o.repeats, stdout, message, sizeof message);
    else
        st = render(&o, &p, message, sizeof message);
    if (st != MANDEL_OK)
        fprintf(stderr, "%s\n", message);
    return st;
}
