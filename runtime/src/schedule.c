/* Schedule labels: "megakernel/stealing/round-robin+local32" and the like
 * (grammar in perma.h), parsed into and formatted from perma_schedule. */
#include "schedule_table.h"

#include <limits.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

/* The label being parsed, the next unread character and where errors go. */
typedef struct cursor {
    const char *label;
    const char *at;
    perma_error *error;
} cursor;

/* One part of a label: the text between separators ('/', '+'). */
typedef struct part {
    const char *text;
    int length;
} part;

static perma_status fail(const cursor *c, const char *fmt, ...)
{
    if (!c->error)
        return PERMA_ERR_ARGUMENT;
    char *message = c->error->message;
    size_t size = sizeof c->error->message;
    c->error->status = PERMA_ERR_ARGUMENT;
    int n = c->label ? snprintf(message, size, "schedule '%s': ", c->label) : 0;
    if (n < 0 || (size_t)n >= size)
        return PERMA_ERR_ARGUMENT;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message + n, size - (size_t)n, fmt, ap);
    va_end(ap);
    return PERMA_ERR_ARGUMENT;
}

static bool steals(perma_strategy strategy)
{
    const perma_strategy_info *row = perma_strategy_row((int)strategy);
    return row && row->steals;
}

/* The label options a strategy's row may list in its `parameters` column
 * ("/d=N"), and the perma_schedule field each sets (an unsigned, 0 = the
 * default). */
typedef struct strategy_option {
    const char *name; /* "d": the label says /d=N */
    size_t field;     /* offsetof the field in perma_schedule */
} strategy_option;

static const strategy_option strategy_options[] = {
    { "d", offsetof(perma_schedule, donation_threshold) },
};

#define OPTION_COUNT (sizeof strategy_options / sizeof strategy_options[0])

static unsigned option_value(const perma_schedule *s, const strategy_option *option)
{
    unsigned value;
    memcpy(&value, (const char *)s + option->field, sizeof value);
    return value;
}

static void set_option_value(perma_schedule *s, const strategy_option *option, unsigned value)
{
    memcpy((char *)s + option->field, &value, sizeof value);
}

/* Whether the row lists the option: "/NAME=N" as one of its
 * space-separated parameters. */
static bool row_takes(const perma_strategy_info *row, const strategy_option *option)
{
    char token[32];
    int n = snprintf(token, sizeof token, "/%s=N", option->name);
    if (!row || n < 0 || (size_t)n >= sizeof token)
        return false;
    for (const char *at = row->parameters; (at = strstr(at, token)) != NULL; at += n)
        if ((at == row->parameters || at[-1] == ' ') && (at[n] == '\0' || at[n] == ' '))
            return true;
    return false;
}

static bool row_steals(const perma_strategy_info *row, const strategy_option *unused)
{
    (void)unused;
    return row->steals;
}

/* The techniques' rows: what their labels take. */
static const perma_technique_info none;
static const perma_technique_info *technique_row(perma_technique technique)
{
    const perma_technique_info *row = perma_technique_row((int)technique);
    return row ? row : &none;
}

/* Consume `separator` if it is next. */
static int accept(cursor *c, char separator)
{
    if (*c->at != separator)
        return 0;
    c->at++;
    return 1;
}

/* The text up to the next separator or the end; consumed. */
static part next_part(cursor *c)
{
    part p = { c->at, (int)strcspn(c->at, "/+") };
    c->at += p.length;
    return p;
}

/* A part as a C string for the *_parse functions; "" when too long to be
 * a name (every name is short). */
static void part_string(part p, char *out, size_t size)
{
    if ((size_t)p.length >= size)
        p.length = 0;
    memcpy(out, p.text, (size_t)p.length);
    out[p.length] = '\0';
}

/* "a, b, c": every name name_at gives from 0 up to the first NULL. */
static void join_names(const char *(*name_at)(int), char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (int i = 0; name_at(i) && used < size; ++i) {
        int n = snprintf(out + used, size - used, "%s%s", i ? ", " : "", name_at(i));
        if (n < 0)
            return;
        used += (size_t)n;
    }
}

static perma_status unknown(const cursor *c, const char *what, part p, const char *(*name_at)(int))
{
    char names[160];
    join_names(name_at, names, sizeof names);
    return fail(c, "unknown %s '%.*s' (%s)", what, p.length, p.text, names);
}

static perma_status parse_technique(cursor *c, perma_technique *out)
{
    char name[32];
    part p = next_part(c);
    part_string(p, name, sizeof name);
    if (perma_technique_parse(name, out) != PERMA_OK)
        return unknown(c, "technique", p, perma_technique_name_at);
    return PERMA_OK;
}

static perma_status parse_strategy(cursor *c, perma_strategy *out)
{
    char name[32];
    part p = next_part(c);
    part_string(p, name, sizeof name);
    if (perma_strategy_parse(name, out) != PERMA_OK)
        return unknown(c, "strategy", p, perma_strategy_name_at);
    return PERMA_OK;
}

/* "a, b or c": the strategies whose rows pass test(row, option), such as
 * those that steal (which a victim may follow). */
typedef bool strategy_test(const perma_strategy_info *row, const strategy_option *option);
static void join_strategies(strategy_test *test, const strategy_option *option, char *out, size_t size)
{
    int count = 0, listed = 0;
    for (int i = 0; perma_strategy_row(i); ++i)
        count += test(perma_strategy_row(i), option);
    out[0] = '\0';
    for (int i = 0; perma_strategy_row(i); ++i) {
        if (!test(perma_strategy_row(i), option))
            continue;
        size_t used = strlen(out);
        const char *separator = listed == 0 ? "" : listed == count - 1 ? " or " : ", ";
        snprintf(out + used, size - used, "%s%s", separator, perma_strategy_name_at(i));
        ++listed;
    }
}

static perma_status parse_victim(cursor *c, perma_strategy strategy, perma_victim *out)
{
    char name[32];
    part p = next_part(c);
    if (!steals(strategy)) {
        char stealing[160];
        join_strategies(row_steals, NULL, stealing, sizeof stealing);
        return fail(c, "victim '%.*s' after strategy '%s' (a victim only follows %s)", p.length, p.text,
                    perma_strategy_name(strategy), stealing);
    }
    part_string(p, name, sizeof name);
    if (perma_victim_parse(name, out) != PERMA_OK)
        return unknown(c, "victim", p, perma_victim_name_at);
    return PERMA_OK;
}

/* A decimal count >= 1 that fits an unsigned; 0 if it is none. */
static unsigned count_of(const char *text, int length)
{
    unsigned long long value = 0;
    if (length <= 0)
        return 0;
    for (int i = 0; i < length; ++i) {
        if (text[i] < '0' || text[i] > '9')
            return 0;
        value = value * 10 + (unsigned)(text[i] - '0');
        if (value > UINT_MAX)
            return 0;
    }
    return (unsigned)value;
}

/* "+localN" or "+wfN" after a technique whose label takes them, the '+'
 * consumed; each once. */
static perma_status parse_plus_option(cursor *c, perma_schedule *s)
{
    static const struct {
        const char *prefix;
        size_t field;
        unsigned most;
        const char *what, *none;
    } options[] = {
        { "local", offsetof(perma_schedule, local_queue_items), PERMA_MAX_LOCAL_QUEUE_ITEMS, "in a local queue",
          "no local queue" },
        { "wf", offsetof(perma_schedule, work_first_items), PERMA_MAX_WORK_FIRST_ITEMS, "on a work-item's stack",
          "the default stack, +wf0 for none" },
    };
    part p = next_part(c);
    for (size_t i = 0; i < sizeof options / sizeof options[0]; ++i) {
        int prefix_length = (int)strlen(options[i].prefix);
        if (p.length < prefix_length || strncmp(p.text, options[i].prefix, (size_t)prefix_length) != 0 ||
            (p.length > prefix_length && (p.text[prefix_length] < '0' || p.text[prefix_length] > '9')))
            continue;
        unsigned value, *out = (unsigned *)((char *)s + options[i].field);
        if (*out)
            return fail(c, "'+%.*s' after another +%sN (give it once)", p.length, p.text, options[i].prefix);
        /* +wf0: no stacks (work-first is on by default). */
        if (options[i].field == offsetof(perma_schedule, work_first_items) && p.length == prefix_length + 1 &&
            p.text[prefix_length] == '0') {
            *out = PERMA_WORK_FIRST_OFF;
            return PERMA_OK;
        }
        value = count_of(p.text + prefix_length, p.length - prefix_length);
        if (!value)
            return fail(c, "'+%.*s' needs a number of items >= 1, e.g. +%s32 (leave it out for %s)", p.length,
                        p.text, options[i].prefix, options[i].none);
        if (value > options[i].most)
            return fail(c, "'+%.*s': at most %u items %s", p.length, p.text, options[i].most, options[i].what);
        *out = value;
        return PERMA_OK;
    }
    return fail(c, "unknown option '+%.*s' (+localN: N items in a local queue; +wfN: work-first, a stack of N "
                "items per work-item, +wf0 none)", p.length, p.text);
}

/* The N of an option part "NAME=N" whose name has name_length characters. */
static perma_status parse_option_count(const cursor *c, part p, int name_length, unsigned *out)
{
    *out = count_of(p.text + name_length + 1, p.length - name_length - 1);
    if (!*out)
        return fail(c, "'/%.*s' needs a number of items >= 1, e.g. /%.*s=64 (leave it out for the "
                    "default)", p.length, p.text, name_length, p.text);
    return PERMA_OK;
}

/* Whether the next part is an option "/NAME=N" rather than a name. */
static bool option_next(const cursor *c)
{
    if (c->at[0] != '/')
        return false;
    return memchr(c->at + 1, '=', strcspn(c->at + 1, "/+")) != NULL;
}

/* "/NAME=N" after the strategy (and victim), the '/' consumed: only an
 * option the strategy's row lists, and only once. */
static perma_status parse_strategy_option(cursor *c, perma_schedule *s)
{
    part p = next_part(c);
    int name_length = (int)(strchr(p.text, '=') - p.text);
    const perma_strategy_info *row = perma_strategy_row((int)s->strategy);
    const strategy_option *option = NULL;
    for (size_t i = 0; i < OPTION_COUNT && !option; ++i)
        if ((int)strlen(strategy_options[i].name) == name_length &&
            strncmp(strategy_options[i].name, p.text, (size_t)name_length) == 0)
            option = &strategy_options[i];
    if (!option || !row_takes(row, option)) {
        char strategies[160] = "";
        if (option)
            join_strategies(row_takes, option, strategies, sizeof strategies);
        const char *name = perma_strategy_name(s->strategy);
        if (!option || !*strategies)
            return fail(c, "unknown option '/%.*s' after strategy '%s' (%s takes %s)", p.length, p.text, name,
                        name, *row->parameters ? row->parameters : "no option");
        return fail(c, "option '/%.*s' after strategy '%s' (/%s=N only follows %s)", p.length, p.text, name,
                    option->name, strategies);
    }
    if (option_value(s, option))
        return fail(c, "'/%.*s' after another /%s=N (give it once)", p.length, p.text, option->name);
    unsigned value;
    perma_status st = parse_option_count(c, p, name_length, &value);
    if (st == PERMA_OK)
        set_option_value(s, option, value);
    return st;
}

/* [/strategy[/victim][/option=N...]] after a technique whose label takes
 * strategies; an option right after the technique follows the default
 * strategy. */
static perma_status parse_strategy_part(cursor *c, perma_schedule *s)
{
    perma_status st = PERMA_OK;
    if (!option_next(c) && accept(c, '/'))
        st = parse_strategy(c, &s->strategy);
    if (st == PERMA_OK && !option_next(c) && accept(c, '/'))
        st = parse_victim(c, s->strategy, &s->victim);
    while (st == PERMA_OK && option_next(c) && accept(c, '/'))
        st = parse_strategy_option(c, s);
    return st;
}

/* [/p=N] after a technique whose label takes a batch limit. */
static perma_status parse_batch_limit(cursor *c, perma_schedule *s)
{
    if (!accept(c, '/'))
        return PERMA_OK;
    part p = next_part(c);
    char name[32];
    part_string(p, name, sizeof name);
    perma_strategy strategy;
    if (perma_strategy_parse(name, &strategy) == PERMA_OK)
        return fail(c, "strategy '%s' with bounded-batches (a strategy is only valid with megakernel)", name);
    if (p.length < 2 || strncmp(p.text, "p=", 2) != 0)
        return fail(c, "unknown option '/%.*s' (bounded-batches takes /p=N: at most N items per "
                    "host iteration)", p.length, p.text);
    return parse_option_count(c, p, 1, &s->batch_limit);
}

/* The label must end here; name what does not fit. */
static perma_status parse_end(const cursor *c, perma_technique technique)
{
    if (!*c->at)
        return PERMA_OK;
    const perma_technique_info *row = technique_row(technique);
    if (!row->strategies && !row->batch_limit && c->at[0] == '/')
        return fail(c, "'%s' after %s (a strategy is only valid with megakernel)", c->at,
                    perma_technique_name(technique));
    if (!row->local_queue && c->at[0] == '+')
        return fail(c, "'%s' after %s (+localN and +wfN are only valid with megakernel)", c->at,
                    perma_technique_name(technique));
    return fail(c, "unexpected '%s' at the end", c->at);
}

perma_status perma_schedule_parse(const char *label, perma_schedule *out, perma_error *error)
{
    cursor c = { label, label, error };
    if (!label)
        return fail(&c, "schedule label is NULL");
    if (!*label)
        return fail(&c, "empty label (e.g. megakernel/shared, kernel-per-procedure)");
    perma_schedule s;
    memset(&s, 0, sizeof s);
    perma_status st = parse_technique(&c, &s.technique);
    const perma_technique_info *row = technique_row(s.technique);
    if (st == PERMA_OK && row->strategies)
        st = parse_strategy_part(&c, &s);
    if (st == PERMA_OK && row->batch_limit)
        st = parse_batch_limit(&c, &s);
    while (st == PERMA_OK && row->local_queue && accept(&c, '+'))
        st = parse_plus_option(&c, &s);
    if (st == PERMA_OK)
        st = parse_end(&c, s.technique);
    if (st != PERMA_OK)
        return st;
    *out = s;
    if (error) {
        error->status = PERMA_OK;
        error->message[0] = '\0';
    }
    return PERMA_OK;
}

/* "/strategy[/victim][/option=N...]": the victim only for a stealing
 * strategy, the options the strategy takes that are not 0; false for an
 * unnamed strategy or victim. */
static bool format_strategy(const perma_schedule *s, char *buf, size_t size)
{
    const char *strategy = perma_strategy_name(s->strategy);
    const char *victim = steals(s->strategy) ? perma_victim_name(s->victim) : "";
    if (!strategy || !victim)
        return false;
    int used = snprintf(buf, size, "/%s%s%s", strategy, *victim ? "/" : "", victim);
    for (size_t i = 0; i < OPTION_COUNT && used >= 0 && (size_t)used < size; ++i) {
        const strategy_option *option = &strategy_options[i];
        if (option_value(s, option) && row_takes(perma_strategy_row((int)s->strategy), option))
            used += snprintf(buf + used, size - (size_t)used, "/%s=%u", option->name, option_value(s, option));
    }
    return true;
}

int perma_schedule_format(const perma_schedule *s, char *buf, size_t size)
{
    const char *technique = perma_technique_name(s->technique);
    const perma_technique_info *row = technique_row(s->technique);
    char strategy[64] = "", limit[32] = "", local[32] = "", work_first[32] = "";
    bool named = technique != NULL;
    if (row->strategies)
        named = named && format_strategy(s, strategy, sizeof strategy);
    if (row->batch_limit && s->batch_limit)
        snprintf(limit, sizeof limit, "/p=%u", s->batch_limit);
    if (row->local_queue && s->local_queue_items)
        snprintf(local, sizeof local, "+local%u", s->local_queue_items);
    if (row->local_queue && s->work_first_items)
        snprintf(work_first, sizeof work_first, "+wf%u",
                 s->work_first_items == PERMA_WORK_FIRST_OFF ? 0u : s->work_first_items);
    if (!named) {
        if (size)
            buf[0] = '\0';
        return -1;
    }
    return snprintf(buf, size, "%s%s%s%s%s", technique, strategy, limit, local, work_first);
}

/* How many names name_at gives. */
static int count_names(const char *(*name_at)(int))
{
    int n = 0;
    while (name_at(n))
        ++n;
    return n;
}

/* The first strategy that steals: where PERMA_SCHEDULES_VICTIMS_ONCE puts
 * the other victim policies. */
static int first_stealing_strategy(void)
{
    for (int st = 0; perma_strategy_name_at(st); ++st)
        if (steals((perma_strategy)st))
            return st;
    return -1;
}

/* Whether `set` leaves out victim v of strategy st (v > 0: not the default). */
static bool left_out(perma_schedule_set set, int st, int v)
{
    if (v == 0 || set == PERMA_SCHEDULES_ALL)
        return false;
    return set == PERMA_SCHEDULES_DEFAULT_VICTIM || st != first_stealing_strategy();
}

perma_status perma_schedule_all(perma_schedule_set set, unsigned index, perma_schedule *out)
{
    if (set != PERMA_SCHEDULES_ALL && set != PERMA_SCHEDULES_VICTIMS_ONCE && set != PERMA_SCHEDULES_DEFAULT_VICTIM)
        return PERMA_ERR_ARGUMENT;
    unsigned at = 0;
    for (int t = 0; perma_technique_row(t); ++t) {
        bool strategies = perma_technique_row(t)->strategies;
        int strategy_count = strategies ? count_names(perma_strategy_name_at) : 1;
        for (int st = 0; st < strategy_count; ++st) {
            int victim_count = strategies && steals((perma_strategy)st) ? count_names(perma_victim_name_at) : 1;
            for (int v = 0; v < victim_count; ++v) {
                if (left_out(set, st, v) || at++ != index)
                    continue;
                memset(out, 0, sizeof *out);
                out->technique = (perma_technique)t;
                out->strategy = (perma_strategy)st;
                out->victim = (perma_victim)v;
                return PERMA_OK;
            }
        }
    }
    return PERMA_ERR_ARGUMENT;
}
