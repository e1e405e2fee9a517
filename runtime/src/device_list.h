/* Device lists ("0:0,1:0", "0:0/2", "all"): the grammar of one entry,
 * shared by PERMA_DEVICE (device.c) and perma_device_list (device_list.c). */
#ifndef PERMA_DEVICE_LIST_H
#define PERMA_DEVICE_LIST_H

#include <stdbool.h>
#include <stddef.h>

#include "perma.h"

/* One entry of a device list. */
typedef struct perma_device_entry {
    bool all;          /* "all": every device of every platform */
    char name[64];     /* NAME of "NAME:D": a platform by name; "": by index */
    int platform;      /* P of "P:D" */
    int device;        /* D */
    unsigned parts;    /* N of "P:D/N" (equal sub-devices); 0: the whole device */
    int part;          /* K of "P:D/N.K"; -1: all N parts */
} perma_device_entry;

/* The message for no platform at all (platform_missing.c): install a
 * driver, or why the registered ones did not load. */
void perma_no_platform_message(char *out, size_t size);

/* Most equal sub-devices an entry may ask for. */
#define PERMA_MAX_SUB_DEVICES 1024u

/* Parse the `length` characters at `text` as one entry: "all", "P:D",
 * "P:D/N" or "P:D/N.K" (decimal numbers, K < N; "/1" is the whole device),
 * where "P:D" may also be "NAME:D" or "NAME" (device 0): a platform whose
 * name or vendor contains NAME (perma_platform_find).  Returns false if
 * malformed. */
bool perma_device_entry_parse(const char *text, size_t length, perma_device_entry *out);

/* Whether the `length` characters at `text` can be a platform NAME:
 * letters, digits, spaces and "()._-", starting with a letter, shorter
 * than perma_device_entry.name, not "all". */
bool perma_platform_name_valid(const char *text, size_t length);

/* The index of the first of `count` platforms whose name or vendor
 * contains `name` (any case), or -1 with the platforms listed in
 * listing ("0 'Intel(R) OpenCL' (Intel(R) Corporation), 1 ..."). */
int perma_platform_find(const cl_platform_id *platforms, cl_uint count, const char *name, char *listing,
                        size_t size);

/* Check every comma-separated entry of `list` and return the first in
 * *first; on a malformed entry return false with its offset and length in
 * *bad_offset, *bad_length. */
bool perma_device_list_first(const char *list, perma_device_entry *first, size_t *bad_offset,
                             size_t *bad_length);

/* Whether `device` can be split into `parts` equal sub-devices; if not,
 * *why says why ("has 2 compute units ..."). */
bool perma_device_splits_equally(cl_device_id device, unsigned parts, char *why, size_t why_size);

/* What PERMA_DEVICE may hold, for messages. */
#define PERMA_DEVICE_FORMS "platform:device (e.g. 0:0) or NAME[:device] (a platform's name or vendor, " \
                           "e.g. intel or pocl:0), either with /N (N equal sub-devices) or /N.K (the K-th " \
                           "of them), 'all', or a comma-separated list"

#endif
