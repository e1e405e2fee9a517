/* Command-line parsing of the mandelbrot program. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mandel_options.h"

void mandel_print_usage(FILE *out)
{
    fprintf(out,
        "usage: perma-mandelbrot [options]\n"
        "Adaptive (Mariani-Silver) Mandelbrot image with perma procedures.\n"
        "  --size WxH            image size (default 1024x768, at most 16384 each)\n"
        "  --region X0,X1,Y0,Y1  part of the complex plane (default -2.2,0.8,-1.125,1.125)\n"
        "  --max-iter N          iteration limit (default 1000)\n"
        "  --min-size N          compute interiors of at most N pixels per pixel (default 16, 2..4096)\n"
        "  -o FILE               output PNG (default mandelbrot.png)\n"
        "  --technique NAME      megakernel, kernel-per-procedure, bounded-batches\n"
        "  --strategy NAME       shared, stealing, donation, stealing-donation (megakernel)\n"
        "  --groups N            persistent work-groups (default: automatic)\n"
        "  --reference           render with the host brute-force loop instead of perma\n"
        "  --stats               print the runtime's statistics\n"
        "  --compare             time the sequential C version and every technique and\n"
        "                        strategy; print a table (no image)\n"
        "  --repeats N           runs per version in --compare, best is reported (default 3)\n"
        "  --help                this text\n"
        "  --version             the version\n"
        "Exit status: 0 ok, 1 runtime failure, 2 bad usage.\n");
}

static mandel_status usage(char *message, size_t size, const char *option, const char *value,
                           const char *expected)
{
    snprintf(message, size, "perma-mandelbrot: %s '%s': expected %s", option, value, expected);
    return MANDEL_ERR_USAGE;
}

static int parse_unsigned(const char *text, unsigned long lo, unsigned long hi, unsigned *out)
{
    if (!text[0] || text[0] == '-' || text[0] == '+')
        return 0;
    char *end;
    errno = 0;
    unsigned long v = strtoul(text, &end, 10);
    if (errno || *end || v < lo || v > hi)
        return 0;
    *out = (unsigned)v;
    return 1;
}

static int parse_size(const char *text, unsigned *w, unsigned *h)
{
    char buf[64];
    const char *x = strchr(text, 'x');
    if (!x || (size_t)(x - text) >= sizeof buf)
        return 0;
    memcpy(buf, text, (size_t)(x - text));
    buf[x - text] = '\0';
    return parse_unsigned(buf, 1, MANDEL_MAX_SIZE, w) && parse_unsigned(x + 1, 1, MANDEL_MAX_SIZE, h);
}

static int parse_region(const char *text, double r[4])
{
    const char *at = text;
    for (int k = 0; k < 4; ++k) {
        char *end;
        errno = 0;
        r[k] = strtod(at, &end);
        if (end == at || errno || !isfinite(r[k]) || *end != (k == 3 ? '\0' : ','))
            return 0;
        at = end + 1;
    }
    return r[0] < r[1] && r[2] < r[3];
}

mandel_status mandel_parse_options(int argc, char **argv, mandel_options *o,
                                   char *message, size_t size)
{
    *o = (mandel_options){
        .width = 1024, .height = 768, .region = { -2.2, 0.8, -1.125, 1.125 },
        .max_iter = 1000, .min_size = MANDEL_DEFAULT_MIN_SIZE, .output = "mandelbrot.png",
        .repeats = 3,
    };
    for (int i = 1; i < argc; ++i) {
        const char *opt = argv[i];
        if (strcmp(opt, "--help") == 0 || strcmp(opt, "-h") == 0) {
            o->help = 1;
            continue;
        }
        if (strcmp(opt, "--version") == 0) {
            o->version = 1;
            continue;
        }
        if (strcmp(opt, "--compare") == 0) {
            o->compare = 1;
            continue;
        }
        if (strcmp(opt, "--reference") == 0) {
            o->reference = 1;
            continue;
        }
        if (strcmp(opt, "--stats") == 0) {
            o->stats = 1;
            continue;
        }
        static const char *const valued[] = { "--size", "--region", "--max-iter", "--min-size", "-o",
            "--technique", "--strategy", "--groups", "--repeats" };
        int known = 0;
        for (size_t k = 0; k < sizeof valued / sizeof valued[0]; ++k)
            known |= strcmp(opt, valued[k]) == 0;
        if (!known) {
            snprintf(message, size, "perma-mandelbrot: unknown option '%s' (try --help)", opt);
            return MANDEL_ERR_USAGE;
        }
        if (i + 1 >= argc) {
            snprintf(message, size, "perma-mandelbrot: %s needs a value", opt);
            return MANDEL_ERR_USAGE;
        }
        const char *v = argv[++i];
        if (strcmp(opt, "--size") == 0 && !parse_size(v, &o->width, &o->height))
            return usage(message, size, opt, v, "WxH with 1..16384 each, e.g. 1024x768");
        if (strcmp(opt, "--region") == 0 && !parse_region(v, o->region))
            return usage(message, size, opt, v, "X0,X1,Y0,Y1 with X0 < X1 and Y0 < Y1");
        if (strcmp(opt, "--max-iter") == 0 && !parse_unsigned(v, 1, MANDEL_MAX_ITER, &o->max_iter))
            return usage(message, size, opt, v, "1..1000000");
        if (strcmp(opt, "--min-size") == 0 && !parse_unsigned(v, 2, 4096, &o->min_size))
            return usage(message, size, opt, v, "2..4096");
        if (strcmp(opt, "--groups") == 0 && !parse_unsigned(v, 1, 4096, &o->run.work_groups))
            return usage(message, size, opt, v, "1..4096");
        if (strcmp(opt, "--repeats") == 0 && !parse_unsigned(v, 1, 100, &o->repeats))
            return usage(message, size, opt, v, "1..100");
        if (strcmp(opt, "--technique") == 0 && perma_technique_parse(v, &o->run.schedule.technique) != PERMA_OK)
            return usage(message, size, opt, v, "megakernel, kernel-per-procedure or bounded-batches");
        if (strcmp(opt, "--strategy") == 0 && perma_strategy_parse(v, &o->run.schedule.strategy) != PERMA_OK)
            return usage(message, size, opt, v, "shared, stealing, donation or stealing-donation");
        if (strcmp(opt, "-o") == 0)
            o->output = v;
    }
    return MANDEL_OK;
}
