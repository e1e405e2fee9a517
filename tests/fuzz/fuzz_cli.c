/*
 * libFuzzer target for the reyes-render option parser: the input is split
 * into argv words (at spaces, newlines and NUL bytes; tabs and other
 * whitespace stay inside words, as a shell could pass them) and given to
 * reyes_cli_parse.  Bad usage is fine; crashes, leaks, sanitizer reports
 * and unterminated messages are not.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_cli.h"

#define MAX_WORDS 256

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int is_separator(char c)
{
    return c == '\0' || c == ' ' || c == '\n';
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0';

    /* argv[0] is the program name, then the words of the input. */
    char *argv[MAX_WORDS + 2];
    int argc = 0;
    argv[argc++] = "reyes-render";
    for (size_t i = 0; i < size && argc <= MAX_WORDS;) {
        while (i < size && is_separator(text[i]))
            ++i;
        if (i == size)
            break;
        argv[argc++] = text + i;
        while (i < size && !is_separator(text[i]))
            ++i;
        text[i] = '\0'; /* i == size is the terminator already */
    }
    argv[argc] = NULL;

    reyes_cli cli;
    /* Small enough that long words truncate the message. */
    char message[128];
    memset(message, 'x', sizeof message);
    perma_cli_status result = reyes_cli_parse(argc, argv, &cli, message, sizeof message);
    if (result != PERMA_CLI_OK && result != PERMA_CLI_USAGE && result != PERMA_CLI_HELP
        && result != PERMA_CLI_VERSION)
        abort();
    if (!memchr(message, '\0', sizeof message))
        abort(); /* the message must always be a terminated string */
    if (result == PERMA_CLI_USAGE && message[0] == '\0')
        abort(); /* bad usage always says why */
    if (result == PERMA_CLI_OK) {
        /* The parser's results must point into argv and be in range. */
        if (!cli.output || cli.model_count >= (size_t)argc)
            abort();
        for (size_t m = 0; m < cli.model_count; ++m)
            if (strlen(cli.models[m]) > size)
                abort();
        /* Run the renderer's range check too; it may refuse what the
         * parser accepts (too many samples), but must not crash. */
        reyes_error error;
        (void)reyes_options_check(&cli.render, &error);
    }
    reyes_cli_free(&cli);
    free(text);
    return 0;
}
