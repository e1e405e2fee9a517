/* The --help text of reyes-render: one line per row of the option table
 * (reyes_cli_options.c). */
#include <stdio.h>

#include "reyes_cli_internal.h"

void reyes_cli_usage(FILE *out, const char *program)
{
    fprintf(out, "usage: %s [MODEL.bpt ...] [options]\n\n"
                 "Render bicubic Bezier patch models (.bpt) with a Reyes pipeline of perma\n"
                 "procedures; with no model, a built-in scene.\n\noptions:\n",
            program);
    for (size_t i = 0; i < cli_option_count; ++i) {
        char prefix[8] = "    ", left[64];
        if (cli_options[i].short_name)
            snprintf(prefix, sizeof prefix, "-%c, ", cli_options[i].short_name);
        snprintf(left, sizeof left, "%s--%s %s", prefix, cli_options[i].name,
                 cli_options[i].argument ? cli_options[i].argument : "");
        fprintf(out, "  %-30s %s\n", left, cli_options[i].help);
    }
    fprintf(out, "\nexit status: 0 ok, 1 rendering or file error, 2 bad usage\n");
}
