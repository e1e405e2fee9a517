/* Output files written together, whole or not at all (reyes.h, *Output*),
 * on perma's output files. */
#include <string.h>

#include "reyes.h"

static reyes_status from_perma(const perma_error *perr, reyes_error *error)
{
    reyes_status status = perr->status == PERMA_ERR_NO_MEMORY ? REYES_ERR_NO_MEMORY
                          : perr->status == PERMA_ERR_ARGUMENT ? REYES_ERR_ARGUMENT
                                                                : REYES_ERR_IO;
    return reyes_fail(error, status, "%s", perr->message);
}

reyes_status reyes_check_output(const char *path, const char *what, reyes_error *error)
{
    reyes_error local;
    if (!error)
        error = &local;
    perma_error perr;
    if (perma_output_check(path, &perr) == PERMA_OK)
        return REYES_OK;
    reyes_status status = from_perma(&perr, error);
    char message[REYES_MESSAGE_MAX];
    snprintf(message, sizeof message, "%s", error->message);
    return reyes_fail(error, status, "%s: %s", what, message);
}

/* Write one file (its temporary, complete and synced, not yet in place). */
static reyes_status write_one(const reyes_output_file *file, perma_output **out, reyes_error *error)
{
    perma_error perr;
    if (perma_output_open(file->path, out, &perr) != PERMA_OK)
        return from_perma(&perr, error);
    reyes_status written = file->write(perma_output_stream(*out), file->data, error);
    /* A failed write's reason (errno) says more than the writer's message. */
    if (perma_output_finish(*out, &perr) != PERMA_OK) {
        *out = NULL;
        return from_perma(&perr, error);
    }
    if (written != REYES_OK) {
        perma_output_discard(*out);
        *out = NULL;
        char message[REYES_MESSAGE_MAX];
        snprintf(message, sizeof message, "%s", error->message);
        return reyes_fail(error, written, "%s: %s", file->path, message);
    }
    return REYES_OK;
}

/* "; so a.png and b.json were not written either" for the other files of a group. */
static void add_others(char *message, size_t size, const reyes_output_file *files, size_t count, size_t failed)
{
    if (count < 2)
        return;
    size_t used = strlen(message);
    used += (size_t)snprintf(message + used, size > used ? size - used : 0, "; so ");
    for (size_t k = 0, listed = 0; k < count && used < size; ++k) {
        if (k == failed)
            continue;
        const char *separator = listed == 0 ? "" : listed + 2 == count ? " and " : ", ";
        used += (size_t)snprintf(message + used, size - used, "%s%s", separator, files[k].path);
        ++listed;
    }
    if (used < size)
        snprintf(message + used, size - used, " %s not written either", count == 2 ? "was" : "were");
}

reyes_status reyes_write_outputs(const reyes_output_file *files, size_t count, reyes_error *error)
{
    reyes_error local;
    if (!error)
        error = &local;
    perma_output *outs[8] = { NULL };
    if (count > sizeof outs / sizeof outs[0])
        return reyes_fail(error, REYES_ERR_ARGUMENT, "more than %zu output files at once",
                          sizeof outs / sizeof outs[0]);
    reyes_status status = REYES_OK;
    size_t k = 0;
    for (; k < count && status == REYES_OK; ++k)
        status = write_one(&files[k], &outs[k], error);
    if (status != REYES_OK) {
        for (size_t j = 0; j < count; ++j)
            perma_output_discard(outs[j]);
        add_others(error->message, sizeof error->message, files, count, k - 1);
        return status;
    }
    for (k = 0; k < count; ++k) {
        perma_error perr;
        if (perma_output_commit(outs[k], &perr) != PERMA_OK) {
            /* Only a rename failed (the directory went away?): say what is in place. */
            for (size_t j = k + 1; j < count; ++j)
                perma_output_discard(outs[j]);
            status = from_perma(&perr, error);
            size_t used = strlen(error->message), size = sizeof error->message;
            for (size_t j = 0; j < k && used < size; ++j)
                used += (size_t)snprintf(error->message + used, size - used, "%s%s", j ? ", " : " (written: ",
                                         files[j].path);
            if (k > 0 && used < size)
                snprintf(error->message + used, size - used, ")");
            return status;
        }
    }
    return REYES_OK;
}
