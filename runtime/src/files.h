#ifndef PERMA_FILES_H
#define PERMA_FILES_H

#include "perma.h"

#include <stdbool.h>

/* files.c: read a whole text file; the message names the path. */
perma_status perma_read_text_file(perma_runtime *rt, const char *path, char **out);
bool perma_is_identifier(const char *s);

#endif
