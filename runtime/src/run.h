#ifndef PERMA_RUN_H
#define PERMA_RUN_H

#include "perma.h"

/* run.c: let go of what the runs learned (perma_destroy). */
void perma_run_release(perma_runtime *rt);

#endif
