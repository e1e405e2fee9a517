/* Host view of the device control block; mirrors kernels/perma_prelude.cl. */
#ifndef PERMA_CONTROL_H
#define PERMA_CONTROL_H

enum {
    PERMA_CTL_OUTSTANDING = 0,
    PERMA_CTL_STATUS = 1,
    PERMA_CTL_EXIT = 2,
    PERMA_CTL_DETAIL_PROC = 3,
    PERMA_CTL_DETAIL_EDGE = 4,
    PERMA_CTL_PROGRESS = 5,
    PERMA_CTL_CLOCK = 6,
    PERMA_CTL_GROW_STARVED = 7,
    PERMA_CTL_HEADER_WORDS = 16
};

enum {
    PERMA_Q_HEAD = 0,
    PERMA_Q_TAIL = 1,
    PERMA_Q_ROOM = 2,
    PERMA_Q_CAP = 3,
    PERMA_Q_DATA = 4,
    PERMA_Q_PUBLISHED = 5,
    PERMA_Q_PEAK = 6,
    PERMA_Q_RELEASED = 7,
    PERMA_QUEUE_WORDS = 8
};

enum { PERMA_GROUP_WORDS = 2 };

enum {
    PERMA_KSTATUS_DONE = 0,
    PERMA_KSTATUS_NEEDS_ROOM = 1, /* DETAIL_PROC: PERMA_DETAIL_STALLED or _STARVED */
    PERMA_KSTATUS_EMIT_LIMIT = 2,
    /* 3 was a bounded wait that ran out: the queues no longer wait. */
    PERMA_KSTATUS_ABORTED = 4
};

#define PERMA_DETAIL_STALLED 0xffffffffu
#define PERMA_DETAIL_STARVED 0xfffffffeu

#define PERMA_EMIT_ERROR_LIMIT 0x10000u
#define PERMA_EMIT_ERROR_UNDECLARED 0x20000u

enum { PERMA_STAT_ITEMS = 0, PERMA_STAT_BATCHES = 1, PERMA_STAT_EMITTED = 2 };

#define PERMA_STAT_PROC_WORDS(max_edges) (2u + (max_edges))

enum {
    PERMA_GSTAT_STEALS = 0,
    PERMA_GSTAT_DONATIONS = 1,
    PERMA_GSTAT_DONATED = 2,
    PERMA_GSTAT_SPILLS = 3,
    PERMA_GSTAT_IDLE_POLLS = 4,
    PERMA_GSTAT_WORDS = 8
};

/* Words of one group's statistics record. */
static inline unsigned perma_stat_group_words(unsigned procs, unsigned max_edges)
{
    return procs * PERMA_STAT_PROC_WORDS(max_edges) + PERMA_GSTAT_WORDS;
}

/* Words of the control block for `queues` queues (sets x procedures). */
static inline unsigned perma_ctl_words(unsigned queues, unsigned groups)
{
    return PERMA_CTL_HEADER_WORDS + queues * PERMA_QUEUE_WORDS + groups * PERMA_GROUP_WORDS;
}

#endif
