/* What reyes-render says when it is interrupted (reyes_interrupt.h). */
#define _GNU_SOURCE /* pthread_setname_np */
#include "reyes_interrupt.h"

#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

static const char *watched_program = "reyes-render";
static pthread_mutex_t outputs = PTHREAD_MUTEX_INITIALIZER; /* held while files are written */
static reyes_interrupt_describe describer;                  /* `outputs` held */
static void *describer_user;

static void stop_signals(sigset_t *set)
{
    sigemptyset(set);
    sigaddset(set, SIGINT);
    sigaddset(set, SIGTERM);
    sigaddset(set, SIGHUP);
}

static const char *signal_name(int number)
{
    return number == SIGINT ? "SIGINT" : number == SIGTERM ? "SIGTERM" : number == SIGHUP ? "SIGHUP" : "a signal";
}

/* The thread that takes the stop signals: wait for a file being written,
 * say what is there, end by the same signal. */
static void *wait_for_stop(void *unused)
{
    (void)unused;
    pthread_setname_np(pthread_self(), "stop-signals");
    sigset_t set;
    stop_signals(&set);
    int number = 0;
    while (sigwait(&set, &number) != 0)
        ;
    pthread_mutex_lock(&outputs);
    char written[1024] = "no image written";
    if (describer)
        describer(describer_user, written, sizeof written);
    /* A progress line on a terminal is left as it was, ended. */
    fprintf(stderr, "%s%s: interrupted by %s; %s\n", isatty(STDERR_FILENO) ? "\n" : "", watched_program,
            signal_name(number), written);
    fflush(stderr);
    /* The default action, in this thread only, which alone takes it now. */
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = SIG_DFL;
    sigaction(number, &action, NULL);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, number);
    pthread_sigmask(SIG_UNBLOCK, &one, NULL);
    raise(number);
    return NULL;
}

void reyes_interrupt_watch(const char *program)
{
    watched_program = program;
    sigset_t set, before;
    stop_signals(&set);
    pthread_sigmask(SIG_BLOCK, &set, &before);
    pthread_t waiter;
    if (pthread_create(&waiter, NULL, wait_for_stop, NULL) != 0) {
        pthread_sigmask(SIG_SETMASK, &before, NULL); /* no thread: the signals' defaults */
        return;
    }
    pthread_detach(waiter);
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
