#ifndef PERMA_BUFFERS_H
#define PERMA_BUFFERS_H

#include "perma.h"

/* buffers.c: copy the host memory of perma_bind_host buffers to the
 * device (PERMA_READ) or back (PERMA_WRITE).  Under PERMA_CHECK_BOUNDS
 * the guard words after each are set before (PERMA_READ) and checked
 * after the run (PERMA_WRITE, before anything is copied back):
 * PERMA_ERR_DEVICE naming a buffer whose guard changed. */
perma_status perma_buffers_copy(perma_runtime *rt, unsigned flag);

#endif
