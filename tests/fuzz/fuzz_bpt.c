/*
 * libFuzzer target for the .bpt loader: the input bytes become the text
 * given to reyes_scene_parse_bpt.  Errors are fine; crashes, leaks and
 * sanitizer reports are not.  Each run also checks the loader's promise
 * that a failed parse leaves the scene as it was.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "reyes.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Errors must read "fuzz.bpt:LINE: ..." with LINE a line of the text. */
static int names_a_line(const char *message, const char *text)
{
    static const char prefix[] = "fuzz.bpt:";
    if (strncmp(message, prefix, sizeof prefix - 1) != 0)
        return 0;
    char *end;
    unsigned long line = strtoul(message + sizeof prefix - 1, &end, 10);
    if (end[0] != ':' || end[1] != ' ')
        return 0;
    unsigned long lines = 1;
    for (const char *c = text; *c; ++c)
        lines += *c == '\n';
    return line >= 1 && line <= lines;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* The parser takes a NUL-terminated string; an embedded NUL just ends it
     * early (the file loader rejects such files before parsing). */
    char *text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0';

    reyes_scene scene;
    reyes_scene_init(&scene);
    reyes_error error = { 0 };
    /* One patch already in the scene, so a rollback to it can be checked. */
    const float first[4][4][3] = { { { 0 } } };
    if (reyes_scene_add_patch(&scene, first, 0u, &error) != REYES_OK)
        abort();

    reyes_status status = reyes_scene_parse_bpt(&scene, text, "fuzz.bpt", 0xff00ff00u, &error);
    if (status != REYES_OK) {
        if (scene.patch_count != 1) /* a failed parse must not add patches */
            abort();
        if (error.status != status || !names_a_line(error.message, text))
            abort(); /* every error carries a message with file:line */
    } else if (scene.patch_count < 2) {
        abort(); /* success means at least one patch was read */
    }
    reyes_scene_free(&scene);
    free(text);
    return 0;
}
