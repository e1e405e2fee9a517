/*
 * What reyes-render says when it is interrupted (SIGINT, SIGTERM, SIGHUP)
 * in one process: "PROGRAM: interrupted by SIGINT; no image written", or
 * which files were written, and then it ends by that signal as before.
 * (Under mpirun, rank 0 says it: mpi_job.h.)
 *
 * The signals are blocked in every thread and taken by one thread with
 * sigwait() (perma_cli_take_stop_signals): PoCL's LLVM installs its own
 * handlers for them at its first compile.  Files are
 * written under a lock that the signal's thread takes before it speaks, so
 * a file being written is finished first: the message is exact and no
 * temporary file is left.
 */
#ifndef REYES_INTERRUPT_H
#define REYES_INTERRUPT_H

#include <stddef.h>

/* What has been written, for the message ("no image written"). */
typedef void (*reyes_interrupt_describe)(void *user, char *out, size_t size);

/* Take the stop signals from here on (call before any thread starts);
 * `program` must outlive the process. */
void reyes_interrupt_watch(const char *program);

/* What the message says has been written: describe(user, ...), called
 * with the output lock held; NULL: "no image written". */
void reyes_interrupt_describe_with(reyes_interrupt_describe describe, void *user);

/* Around the writing of output files: the lock; ending it, `describe`
 * (if not NULL) says from then on what is written. */
void reyes_interrupt_outputs_begin(void);
void reyes_interrupt_outputs_end(reyes_interrupt_describe describe, void *user);

#endif
