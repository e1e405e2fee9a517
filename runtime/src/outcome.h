#ifndef PERMA_OUTCOME_H
#define PERMA_OUTCOME_H

#include "perma.h"
#include "perma_abi.h"

/* outcome.c: the error of a launch's failure status (not DONE or
 * NEEDS_ROOM). */
perma_status perma_outcome_error(perma_runtime *rt, const perma_ctl_header *outcome);

#endif
