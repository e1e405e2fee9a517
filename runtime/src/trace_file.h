#ifndef PERMA_TRACE_FILE_H
#define PERMA_TRACE_FILE_H

#include "perma.h"

/* trace_file.c: every traced run of the process in its file. */
void perma_trace_file_run_begins(double start);           /* a traced run starts */
perma_status perma_trace_write(perma_runtime *rt);         /* at the end of a run */

#endif
