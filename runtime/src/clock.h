#ifndef PERMA_CLOCK_H
#define PERMA_CLOCK_H

#include "perma.h"

/* clock.c: the host clock every deadline and trace timestamp uses; the
 * run's time and stall limits. */
double perma_now(void);
double perma_cpu_now(void);
double perma_time_limit(const perma_config *config);
double perma_stall_limit(const perma_config *config);

#endif
