/*
 * --compare: the sequential C versions and the perma version under every
 * schedule on the same image, through the examples' harness
 * (examples/common/example_compare.h), each perma image checked against
 * the sequential one.
 */
#include <stdlib.h>
#include <string.h>

#include "example_compare.h"
#include "mandel.h"

typedef struct compare_data {
    mandel_run run;     /* the image of every version but the sequential one */
    uint32_t *expected; /* the sequential Mariani-Silver image */
    size_t pixels;
} compare_data;

static int run_sequential(void *data)
{
    compare_data *d = data;
    return mandel_sequential(&d->run.params, d->expected);
}

static int run_brute_force(void *data)
{
    compare_data *d = data;
    mandel_brute_force(&d->run.params, d->run.counts);
    return 0;
}

static const char *check(void *data)
{
    compare_data *d = data;
    return memcmp(d->run.counts, d->expected, d->pixels * sizeof *d->expected) == 0 ? "identical" : "DIFFERS";
}

mandel_status mandel_compare(const mandel_params *p, unsigned work_groups, unsigned repeats,
                             FILE *out, char *message, size_t size)
{
    compare_data d = { { *p, NULL, 0 }, NULL, (size_t)p->width * p->height };
    d.expected = malloc(d.pixels * sizeof *d.expected);
    d.run.counts = malloc(d.pixels * sizeof *d.run.counts);
    example_compare ex = { &mandel_program, &d.run, check, &d, "image", 0 };
    mandel_status st = MANDEL_OK;
    double brute = -1, sequential = -1;
    if (d.expected && d.run.counts) {
        fprintf(out, "%ux%u pixels, max_iter %u, min_size %u; best of %u runs after a warm-up; build excluded\n",
                p->width, p->height, p->max_iter, p->min_size, repeats);
        brute = example_compare_best(repeats, run_brute_force, &d);
        sequential = example_compare_best(repeats, run_sequential, &d);
    }
    if (sequential < 0) {
        snprintf(message, size, "perma-mandelbrot: --compare: out of memory for %zu pixels", d.pixels);
        st = MANDEL_ERR_RUNTIME;
    } else {
        example_compare_header(&ex, out);
        example_compare_row(&ex, out, "sequential C, Mariani-Silver", sequential, sequential, -1, 0, "reference");
        example_compare_row(&ex, out, "sequential C, brute force", brute, sequential, -1, 0, check(&d));
        if (example_compare_schedules(&ex, work_groups, repeats, sequential, out, message, size) != 0)
            st = MANDEL_ERR_RUNTIME;
    }
    free(d.expected);
    free(d.run.counts);
    return st;
}
