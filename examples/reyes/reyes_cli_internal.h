/* The pieces of reyes-render's command line, shared by the argument walk
 * (reyes_cli.c), the option table (reyes_cli_options.c), the value
 * parsers (reyes_cli_values.c) and the --help text (reyes_cli_usage.c). */
#ifndef REYES_CLI_INTERNAL_H
#define REYES_CLI_INTERNAL_H

#include <stddef.h>

#include "reyes_cli.h"

typedef int (*option_handler)(reyes_cli *cli, const char *value, char *message, size_t size);

/* Where an option without a handler puts its value (reyes_cli_options.c). */
typedef struct cli_field cli_field;

typedef struct cli_option {
    const char *name;      /* long name without dashes */
    char short_name;       /* 0 if none */
    const char *argument;  /* NULL for a flag */
    option_handler handle; /* NULL: `field` says what the option sets */
    const char *help;
    const cli_field *field;
} cli_option;

/* The option table, in --help order. */
extern const cli_option cli_options[];
extern const size_t cli_option_count;

/* Apply `value` (NULL for a flag) of `option` to *cli: REYES_CLI_OK, or
 * REYES_CLI_USAGE with a message. */
int cli_option_apply(const cli_option *option, reyes_cli *cli, const char *value, char *message, size_t size);

/* Write the message (`format` with two strings) and return REYES_CLI_USAGE. */
int cli_usage_error(char *message, size_t size, const char *format, const char *a, const char *b);

/* 1 and *out if `text` is a whole decimal number 0..max (no sign, no
 * spaces); else 0. */
int cli_parse_unsigned(const char *text, unsigned long max, unsigned *out);

/* 1 and *out if `text` is a finite number; else 0. */
int cli_parse_float(const char *text, float *out);

/* "WxH" with both sides in 1..REYES_MAX_SIZE; 0 if malformed. */
int cli_parse_wxh(const char *value, unsigned *w, unsigned *h);

/* Parse exactly `count` comma-separated numbers of `option` into out[];
 * `shape` shows the expected form in the message (e.g. "dx,dy,dz"). */
int cli_parse_float_list(const char *option, const char *value, float *out, int count, const char *shape,
                         char *message, size_t size);

#endif
