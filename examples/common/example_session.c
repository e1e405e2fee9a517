/* A built perma program of an example, run again and again (example_session.h). */
#include "example_session.h"

#include <stdlib.h>

struct example_session {
    const example_program *program;
    void *data;
    perma_runtime *rt;
};

static int fail(example_session *s, const char *step, char *message, size_t size)
{
    snprintf(message, size, "%s: %s: %s", s->program->name, step, perma_errmsg(s->rt));
    return 1;
}

int example_session_create(const example_program *program, void *data, const example_run_options *options,
                           example_session **out, char *message, size_t size)
{
    *out = NULL;
    example_session *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(message, size, "%s: out of memory for the session", program->name);
        return 1;
    }
    s->program = program;
    s->data = data;
    perma_config config;
    perma_config_init(&config);
    config.schedule = options->schedule;
    config.work_groups = options->work_groups;
    perma_error error;
    if (perma_create(&config, &s->rt, &error) != PERMA_OK) {
        snprintf(message, size, "%s: perma_create: %s", program->name, error.message);
        free(s);
        return 1;
    }
    const char *step = "registering procedures";
    int status = 0;
    if (program->build(s->rt, data, &step) != PERMA_OK)
        status = fail(s, step, message, size);
    else if (perma_build(s->rt) != PERMA_OK)
        status = fail(s, "building the program", message, size);
    if (status != 0) {
        example_session_destroy(s);
        return status;
    }
    *out = s;
    return 0;
}

int example_session_run(example_session *s, char *message, size_t size)
{
    if (s->program->seed(s->rt, s->data) != PERMA_OK)
        return fail(s, "seeding", message, size);
    if (perma_run(s->rt) != PERMA_OK)
        return fail(s, "running", message, size);
    return 0;
}

perma_runtime *example_session_runtime(example_session *s)
{
    return s->rt;
}

void example_session_destroy(example_session *s)
{
    if (!s)
        return;
    perma_destroy(s->rt);
    free(s);
}

int example_session_once(const example_program *program, void *data, const example_run_options *options,
                         FILE *out, int stats, char *message, size_t size)
{
    example_session *s;
    int status = example_session_create(program, data, options, &s, message, size);
    if (status == 0 && out)
        fprintf(out, "device: %s\n", perma_device_summary(s->rt));
    if (status == 0)
        status = example_session_run(s, message, size);
    if (status == 0 && out && stats)
        perma_print_stats(s->rt, out);
    example_session_destroy(s);
    return status;
}
