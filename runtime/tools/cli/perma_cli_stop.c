/* Stop signals taken by one thread of the program's (perma_cli.h). */
#define _GNU_SOURCE /* pthread_setname_np */
#include "perma_cli.h"

#include <pthread.h>
#include <signal.h>
#include <string.h>

static void (*stop_handler)(int number);

static void stop_signals(sigset_t *set)
{
    sigemptyset(set);
    sigaddset(set, SIGINT);
    sigaddset(set, SIGTERM);
    sigaddset(set, SIGHUP);
}

/* Wait for a stop signal, let the program speak, end by the signal. */
static void *wait_for_stop(void *unused)
{
    (void)unused;
    pthread_setname_np(pthread_self(), "stop-signals"); /* tests tell it apart */
    sigset_t set;
    stop_signals(&set);
    int number = 0;
    while (sigwait(&set, &number) != 0)
        ;
    stop_handler(number);
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

int perma_cli_take_stop_signals(void (*stopped)(int number))
{
    stop_handler = stopped;
    sigset_t set, before;
    stop_signals(&set);
    pthread_sigmask(SIG_BLOCK, &set, &before);
    pthread_t waiter;
    if (pthread_create(&waiter, NULL, wait_for_stop, NULL) != 0) {
        pthread_sigmask(SIG_SETMASK, &before, NULL); /* no thread: the signals' defaults */
        return -1;
    }
    pthread_detach(waiter);
    return 0;
}

const char *perma_cli_signal_name(int number)
{
    return number == SIGINT ? "SIGINT" : number == SIGTERM ? "SIGTERM" : number == SIGHUP ? "SIGHUP" : "a signal";
}
