/* What reyes-render says when it is interrupted (reyes_interrupt.h). */
#include "reyes_interrupt.h"

#include <perma_cli.h>
#include <pthread.h>
#include <stdio.h>
#include <unistd.h>

static const char *watched_program = "reyes-render";
static pthread_mutex_t outputs = PTHREAD_MUTEX_INITIALIZER; /* held while files are written */
static reyes_interrupt_describe describer;                  /* `outputs` held */
static void *describer_user;

/* Wait for a file being written, say what is there (the process then
 * ends by the signal). */
static void stopped(int number)
{
    pthread_mutex_lock(&outputs);
    char written[1024] = "no image written";
    if (describer)
        describer(describer_user, written, sizeof written);
    /* A progress line on a terminal is left as it was, ended. */
    fprintf(stderr, "%s%s: interrupted by %s; %s\n", isatty(STDERR_FILENO) ? "\n" : "", watched_program,
            perma_cli_signal_name(number), written);
    fflush(stderr);
}

void reyes_interrupt_watch(const char *program)
{
    watched_program = program;
    perma_cli_take_stop_signals(stopped);
}

void reyes_interrupt_describe_with(reyes_interrupt_describe describe, void *user)
{
    pthread_mutex_lock(&outputs);
    describer = describe;
    describer_user = user;
    pthread_mutex_unlock(&outputs);
}

void reyes_interrupt_outputs_begin(void)
{
    pthread_mutex_lock(&outputs);
}

void reyes_interrupt_outputs_end(reyes_interrupt_describe describe, void *user)
{
    if (describe) {
        describer = describe;
        describer_user = user;
    }
    pthread_mutex_unlock(&outputs);
}
