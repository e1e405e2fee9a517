/* The command-line options the examples' programs share (example_options.h). */
#include "example_options.h"

#include <string.h>

void example_options_init(example_options *o, perma_cli_option rows[EXAMPLE_OPTION_ROWS], perma_cli_table *table)
{
    *o = (example_options){ .repeats = 3 };
    const perma_cli_option shared[EXAMPLE_OPTION_ROWS] = {
        { PERMA_CLI_CHOICE_OF("technique", "NAME", &o->run.schedule.technique, perma_cli_technique_name,
                              "how perma runs the procedures (default megakernel)") },
        { PERMA_CLI_CHOICE_OF("strategy", "NAME", &o->run.schedule.strategy, perma_cli_strategy_name,
                              "megakernel: how its groups share the queues (default shared)") },
        { PERMA_CLI_WHOLE("groups", "N", &o->run.work_groups, 1, 4096, "persistent work-groups (default: as many "
                                                                        "as fit)") },
        { PERMA_CLI_FLAG("stats", &o->stats, "print the runtime's statistics") },
        { PERMA_CLI_FLAG("compare", &o->compare,
                         "time sequential C and perma under every technique and strategy; print a table") },
        { PERMA_CLI_WHOLE("repeats", "N", &o->repeats, 1, 100,
                          "runs per version in --compare, the best is reported (default 3)") },
    };
    memcpy(rows, shared, sizeof shared);
    *table = (perma_cli_table){ "perma options", rows, EXAMPLE_OPTION_ROWS };
}
