#ifndef PERMA_PROGRAM_H
#define PERMA_PROGRAM_H

#include "perma.h"

/* program.c: perma_build after the call's start (perma_call_begin): build
 * unless built; let go of the program and its kernels. */
perma_status perma_build_program(perma_runtime *rt);
void perma_release_program(perma_runtime *rt);

#endif
