#ifndef PERMA_PROGRAM_CACHE_H
#define PERMA_PROGRAM_CACHE_H

#include "perma.h"
#include "strbuf.h"

#include <stdbool.h>

/* program_cache.c: the disk cache of built programs.  An entry is one
 * build's key (everything its binary depends on) and file, worked out once
 * for the load, the lock and the store; without a cache it is not usable
 * and they all do nothing.  perma_cache_load gives the built program from
 * the cache (NULL: none; a damaged entry is removed with a notice).
 * perma_cache_lock takes the entry's build lock, waiting (bounded) while
 * another process or thread holds it: after it, load again before
 * building.  perma_cache_store stores rt->build.program, built from source,
 * when its build took enough CPU time (true: stored);
 * perma_cache_entry_close lets go of the lock. */
typedef struct perma_cache_entry {
    bool usable;
    perma_strbuf key;
    char dir[1024];
    char path[1100];
    bool stores;          /* the implementation's programs are stored here (not PoCL's) */
    int lock_fd;          /* the build lock while held; -1 otherwise */
    double waited;        /* seconds perma_cache_lock waited */
} perma_cache_entry;
void perma_cache_entry_open(perma_runtime *rt, const char *source, const char *options, perma_cache_entry *entry);
void perma_cache_entry_close(perma_cache_entry *entry);
cl_program perma_cache_load(perma_runtime *rt, const perma_cache_entry *entry, const char *options);
bool perma_cache_lock(perma_cache_entry *entry);
bool perma_cache_store(perma_runtime *rt, const perma_cache_entry *entry, double cpu_seconds);

#endif
