#ifndef PERMA_BUFFERS_H
#define PERMA_BUFFERS_H

#include "perma.h"

/* buffers.c: copy the host memory of perma_bind_host buffers to the
 * device (PERMA_READ) or back (PERMA_WRITE). */
perma_status perma_buffers_copy(perma_runtime *rt, unsigned flag);

#endif
