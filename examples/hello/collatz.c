/*
 * A first perma program: two procedures.
 *
 *   step:   one Collatz step on a number; emits the next number to itself,
 *           or, once the number reaches 1, a "finished" record to `record`.
 *   record: adds the starting value's step count to a histogram, and to
 *           the reduction `longest` (the most steps of any start).
 *
 * The host seeds `step` with the numbers 1..N, runs until no work is left,
 * and prints the histogram and the runtime's statistics.
 */
#include <perma.h>
#include <perma_cli.h>

#include <stdio.h>
#include <stdlib.h>

/* Item types are shared by both procedures, so they go in a common source. */
static const char *types =
    "struct walk { uint start; uint value; uint steps; };\n"
    "struct finished { uint start; uint steps; };\n";

static const char *step_source =
    "void step(perma_ctx *ctx, __local const struct walk *w)\n"
    "{\n"
    "    if (w->value == 1u) {\n"
    "        struct finished f = { w->start, w->steps };\n"
    "        emit_record(ctx, &f);\n"
    "        return;\n"
    "    }\n"
    "    struct walk next = { w->start, (w->value & 1u) ? 3u * w->value + 1u : w->value / 2u, w->steps + 1u };\n"
    "    emit_step(ctx, &next);\n"
    "}\n";

static const char *record_source =
    "void record(perma_ctx *ctx, __local const struct finished *f)\n"
    "{\n"
    "    atomic_inc(&ctx->buf.histogram[min(f->steps, 127u)]);\n"
    "    reduce_longest(ctx, f->steps);\n"
    "}\n";

struct walk { unsigned start, value, steps; };

static int fail(perma_runtime *rt, const char *what)
{
    fprintf(stderr, "perma-collatz: %s: %s\n", what, perma_errmsg(rt));
    perma_destroy(rt);
    return 1;
}

int main(int argc, char **argv)
{
    /* The command line through perma_cli.h, the engine of perma's programs:
     * N (checked against its range), --help, --version; bad usage exits 2. */
    unsigned n = 10000;
    const perma_cli_option count = {
        PERMA_CLI_WHOLE(NULL, "N", &n, 1, 1000000, "count the stopping times of 1..N (default 10000)"),
    };
    const perma_cli cli = {
        .program = "perma-collatz",
        .synopsis = "[N]",
        .about = "Counts the Collatz steps of 1..N with two perma procedures and prints\n"
                 "a histogram of them and the runtime's statistics.",
        .operand = &count,
        .max_operands = 1,
        .notes = "exit status: 0 ok, 1 a perma failure, 2 bad usage",
    };
    char message[PERMA_CLI_MESSAGE_MAX];
    perma_cli_status parsed = perma_cli_parse(&cli, argc, argv, message, sizeof message);
    if (parsed != PERMA_CLI_OK)
        return perma_cli_exit_status(parsed);

    perma_config config;
    perma_config_init(&config);
    perma_runtime *rt;
    perma_error error;
    if (perma_create(&config, &rt, &error) != PERMA_OK) {
        fprintf(stderr, "perma-collatz: %s\n", error.message);
        return 1;
    }
    printf("device: %s\n", perma_device_summary(rt));

    perma_procedure step = {
        .name = "step", .item_type = "struct walk", .item_size = sizeof(struct walk),
        .threads_per_item = 1, .source = step_source, .source_file = "collatz_step.cl",
        .function = "step",
        .emits = { { "step", 1 }, { "record", 1 } },
    };
    perma_procedure record = {
        .name = "record", .item_type = "struct finished", .item_size = 8,
        .threads_per_item = 1, .source = record_source, .source_file = "collatz_record.cl",
        .function = "record",
    };
    perma_proc step_id, record_id;
    if (perma_add_source(rt, types, "collatz_types.cl") != PERMA_OK ||
        perma_register(rt, &step, &step_id) != PERMA_OK ||
        perma_register(rt, &record, &record_id) != PERMA_OK)
        return fail(rt, "registering procedures");

    /* An array shared by all items: a buffer, updated with atomics.  One
     * value: a reduction, set after the run. */
    unsigned histogram[128] = { 0 }, longest = 0;
    if (perma_bind_host(rt, "histogram", "__global uint *", histogram, sizeof histogram, PERMA_READ_WRITE) != PERMA_OK ||
        perma_declare_reduction(rt, "longest", PERMA_REDUCE_MAX, PERMA_TYPE_UINT, &longest) != PERMA_OK)
        return fail(rt, "binding buffers");

    struct walk *seeds = malloc(n * sizeof *seeds);
    if (!seeds)
        return fail(rt, "out of memory");
    for (unsigned i = 0; i < n; ++i)
        seeds[i] = (struct walk){ i + 1, i + 1, 0 };
    perma_status st = perma_seed(rt, step_id, seeds, n);
    free(seeds);
    if (st != PERMA_OK)
        return fail(rt, "seeding");
    if (perma_run(rt) != PERMA_OK)
        return fail(rt, "running");

    printf("Collatz stopping times of 1..%u (longest: %u steps)\n", n, longest);
    for (unsigned s = 0; s < 128; s += 8) {
        unsigned bucket = 0;
        for (unsigned k = s; k < s + 8; ++k)
            bucket += histogram[k];
        if (bucket && s + 8 < 128)
            printf("  %3u..%3u steps: %u\n", s, s + 7, bucket);
        else if (bucket)
            printf("  %3u+     steps: %u\n", s, bucket);
    }
    perma_print_stats(rt, stdout);
    perma_destroy(rt);
    return 0;
}
