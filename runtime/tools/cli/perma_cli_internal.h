/* What the parts of the command-line engine share: the argv walk
 * (perma_cli_parse.c), the values (perma_cli_values.c) and --help
 * (perma_cli_help.c). */
#ifndef PERMA_CLI_INTERNAL_H
#define PERMA_CLI_INTERNAL_H

#include "perma_cli.h"

/* The values `option` accepts, for a complaint ("a whole number in 1..64",
 * "WxH with sides in 1..16384", "none, stitch or wedge") or, with
 * `for_help`, to append to its help ("N in 1..64", "NAME: none, stitch or
 * wedge"); "" when anything goes (a text, a flag, a custom value, a whole
 * number of the full range). */
void perma_cli_accepted(const perma_cli_option *option, int for_help, char *out, size_t size);

/* The name of a CHOICE row's value k, NULL past the last. */
const char *perma_cli_choice_name(const perma_cli_option *option, unsigned k);

/* The rows every program has (--help, --version), listed after its own. */
const perma_cli_option *perma_cli_own_rows(size_t *count);

#endif
