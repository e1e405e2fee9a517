#ifndef PERMA_FILES_H
#define PERMA_FILES_H

#include "perma.h"

#include <stdbool.h>

/* files.c: read a whole text file; the message names the path. */
perma_status perma_read_text_file(perma_runtime *rt, const char *path, char **out);
bool perma_is_identifier(const char *s);

/* Why `name` cannot name a procedure, its function, a buffer or a
 * reduction (the generated program would not compile, or would clash
 * with the runtime's code): "an OpenCL C keyword", "an OpenCL C type", ...;
 * NULL if it can. */
const char *perma_reserved_name(const char *name);

/* The size in bytes of a built-in OpenCL C scalar or vector type ("uint"
 * 4, "float3" 16); 0 for any other name. */
size_t perma_cl_type_size(const char *name);

/* The size of what a pointer type such as "__global const uint *" points
 * to, when it is a built-in scalar or vector (its name into pointee,
 * "uint"; qualifiers and "unsigned int" understood); 0 otherwise (a
 * struct, a pointer to pointers, not a pointer). */
size_t perma_cl_pointee_size(const char *pointer_type, char *pointee, size_t size);

#endif
