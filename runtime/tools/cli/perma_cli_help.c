/*
 * --help from the table: the usage lines, what the program does, then a
 * line per row ("  -o, --output FILE   text (the accepted values)")
 * wrapped at 79 columns, then the notes.  docs/help_to_man.py turns this
 * layout into the man pages.
 */
#include <string.h>

#include "perma_cli_internal.h"

#define WIDTH 79       /* the lines' length */
#define WIDEST_LEFT 30 /* a longer "--name ARG" has its text on the next line */

/* "-o, --output FILE", "    --size WxH", or an operand's "N". */
static void left_text(const perma_cli_option *o, char *out, size_t size)
{
    if (!o->name)
        snprintf(out, size, "%s", o->argument ? o->argument : "");
    else if (o->short_name)
        snprintf(out, size, "-%c, --%s%s%s", o->short_name, o->name, o->argument ? " " : "",
                 o->argument ? o->argument : "");
    else
        snprintf(out, size, "    --%s%s%s", o->name, o->argument ? " " : "", o->argument ? o->argument : "");
}

/* The help and the values the row accepts: "text (N in 1..64)", or
 * "text (default 4; N in 1..64)" when the text ends in parentheses. */
static void row_text(const perma_cli_option *o, char *out, size_t size)
{
    char accepted[PERMA_CLI_MESSAGE_MAX];
    const char *help = o->help ? o->help : "";
    size_t n = strlen(help);
    perma_cli_accepted(o, 1, accepted, sizeof accepted);
    if (!accepted[0])
        snprintf(out, size, "%s", help);
    else if (n && help[n - 1] == ')')
        snprintf(out, size, "%.*s; %s)", (int)(n - 1), help, accepted);
    else
        snprintf(out, size, "%s%s(%s)", help, n ? " " : "", accepted);
}

/* `text` from column `column` on, wrapped at WIDTH; the first line
 * continues what is already `at` columns long. */
static void wrap(FILE *out, const char *text, size_t column, size_t at)
{
    while (*text) {
        size_t room = WIDTH > column ? WIDTH - column : 20, length = strlen(text);
        size_t cut = length;
        if (length > room) {
            cut = room;
            while (cut > 0 && text[cut] != ' ')
                --cut;
            if (cut == 0) /* one long word: let it run past */
                cut = strcspn(text, " ");
        }
        fprintf(out, "%*s%.*s\n", (int)(column > at ? column - at : 0), "", (int)cut, text);
        text += cut;
        while (*text == ' ')
            ++text;
        at = 0;
    }
}

static void print_row(FILE *out, const perma_cli_option *o, size_t column)
{
    char left[128], text[2 * PERMA_CLI_MESSAGE_MAX];
    left_text(o, left, sizeof left);
    row_text(o, text, sizeof text);
    fprintf(out, "  %s", left);
    size_t at = 2 + strlen(left);
    if (at + 2 > column) { /* too wide: the text on the next line */
        fprintf(out, "\n");
        at = 0;
    }
    if (text[0])
        wrap(out, text, column, at);
    else
        fprintf(out, "\n");
}

/* The column of the rows' text: after the widest left part that fits. */
static size_t text_column(const perma_cli *cli)
{
    char left[128];
    size_t widest = 10, count;
    const perma_cli_option *own = perma_cli_own_rows(&count);
    for (size_t t = 0; t <= cli->table_count; ++t) {
        const perma_cli_option *rows = t < cli->table_count ? cli->tables[t].options : own;
        size_t n = t < cli->table_count ? cli->tables[t].count : count;
        for (size_t i = 0; i < n; ++i) {
            left_text(&rows[i], left, sizeof left);
            if (strlen(left) <= WIDEST_LEFT && strlen(left) > widest)
                widest = strlen(left);
        }
    }
    if (cli->operand) {
        left_text(cli->operand, left, sizeof left);
        widest = strlen(left) <= WIDEST_LEFT && strlen(left) > widest ? strlen(left) : widest;
    }
    return 2 + widest + 2;
}

void perma_cli_help(const perma_cli *cli, FILE *out)
{
    const char *synopsis = cli->synopsis ? cli->synopsis : "[options]";
    for (int first = 1; first || *synopsis; first = 0) {
        size_t n = strcspn(synopsis, "\n");
        fprintf(out, "%s %s %.*s\n", first ? "usage:" : "      ", cli->program, (int)n, synopsis);
        synopsis += n + (synopsis[n] == '\n');
    }
    if (cli->about && cli->about[0])
        fprintf(out, "\n%s%s", cli->about, cli->about[strlen(cli->about) - 1] == '\n' ? "" : "\n");
    size_t column = text_column(cli), count;
    if (cli->operand && cli->operand->help) {
        fprintf(out, "\narguments:\n");
        print_row(out, cli->operand, column);
    }
    for (size_t t = 0; t < cli->table_count; ++t) {
        fprintf(out, "\n%s:\n", cli->tables[t].heading);
        for (size_t i = 0; i < cli->tables[t].count; ++i)
            print_row(out, &cli->tables[t].options[i], column);
    }
    if (!cli->table_count)
        fprintf(out, "\noptions:\n");
    const perma_cli_option *own = perma_cli_own_rows(&count);
    for (size_t i = 0; i < count; ++i)
        print_row(out, &own[i], column);
    if (cli->notes && cli->notes[0])
        fprintf(out, "\n%s%s", cli->notes, cli->notes[strlen(cli->notes) - 1] == '\n' ? "" : "\n");
}
