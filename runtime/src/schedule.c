/* Schedule labels: "megakernel/stealing/round-robin+local32" and the like
 * (grammar in perma.h), parsed into and formatted from perma_schedule. */
#include "internal.h"

#include <limits.h>
#include <stdarg.h>
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

static int steals(perma_strategy strategy)
{
    return strategy == PERMA_STRATEGY_STEALING || strategy == PERMA_STRATEGY_STEALING_DONATION;
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

static const char *technique_at(int i) { return perma_technique_name((perma_technique)i); }
static const char *strategy_at(int i) { return perma_strategy_name((perma_strategy)i); }
static const char *victim_at(int i) { return perma_victim_name((perma_victim)i); }

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
        return unknown(c, "technique", p, technique_at);
    return PERMA_OK;
}

static perma_status parse_strategy(cursor *c, perma_strategy *out)
{
    char name[32];
    part p = next_part(c);
    part_string(p, name, sizeof name);
    if (perma_strategy_parse(name, out) != PERMA_OK)
        return unknown(c, "strategy", p, strategy_at);
    return PERMA_OK;
}

static perma_status parse_victim(cursor *c, perma_strategy strategy, perma_victim *out)
{
    char name[32];
    part p = next_part(c);
    if (!steals(strategy))
        return fail(c, "victim '%.*s' after strategy '%s' (a victim only follows stealing or "
                    "stealing-donation)", p.length, p.text, perma_strategy_name(strategy));
    part_string(p, name, sizeof name);
    if (perma_victim_parse(name, out) != PERMA_OK)
        return unknown(c, "victim", p, victim_at);
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

/* "+localN" after a megakernel strategy, the '+' consumed. */
static perma_status parse_local(cursor *c, unsigned *out)
{
    static const char prefix[] = "local";
    const int prefix_length = (int)sizeof prefix - 1;
    part p = next_part(c);
    if (p.length < prefix_length || strncmp(p.text, prefix, (size_t)prefix_length) != 0)
        return fail(c, "unknown option '+%.*s' (+localN: N items in a local queue)", p.length, p.text);
    *out = count_of(p.text + prefix_length, p.length - prefix_length);
    if (!*out)
        return fail(c, "'+%.*s' needs a number of items >= 1, e.g. +local32 (leave it out for no "
                    "local queue)", p.length, p.text);
    if (*out > PERMA_MAX_LOCAL_QUEUE_ITEMS)
        return fail(c, "'+%.*s': at most %u items in a local queue", p.length, p.text,
                    (unsigned)PERMA_MAX_LOCAL_QUEUE_ITEMS);
    return PERMA_OK;
}

/* What may follow "megakernel": [/strategy[/victim]][+localN]. */
static perma_status parse_megakernel(cursor *c, perma_schedule *s)
{
    perma_status st = PERMA_OK;
    if (accept(c, '/'))
        st = parse_strategy(c, &s->strategy);
    if (st == PERMA_OK && accept(c, '/'))
        st = parse_victim(c, s->strategy, &s->victim);
    if (st == PERMA_OK && accept(c, '+'))
        st = parse_local(c, &s->local_queue_items);
    return st;
}

/* What may follow "bounded-batches": [/p=N]. */
static perma_status parse_bounded(cursor *c, perma_schedule *s)
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
    s->batch_limit = count_of(p.text + 2, p.length - 2);
    if (!s->batch_limit)
        return fail(c, "'/%.*s' needs a number of items >= 1, e.g. /p=64 (leave it out for the "
                    "default)", p.length, p.text);
    return PERMA_OK;
}

/* The label must end here; name what does not fit. */
static perma_status parse_end(const cursor *c, perma_technique technique)
{
    if (!*c->at)
        return PERMA_OK;
    if (technique == PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE && c->at[0] == '/')
        return fail(c, "'%s' after kernel-per-procedure (a strategy is only valid with megakernel)",
                    c->at);
    if (technique != PERMA_TECHNIQUE_MEGAKERNEL && c->at[0] == '+')
        return fail(c, "'%s' after %s (+localN is only valid with megakernel)", c->at,
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
    if (st == PERMA_OK && s.technique == PERMA_TECHNIQUE_MEGAKERNEL)
        st = parse_megakernel(&c, &s);
    if (st == PERMA_OK && s.technique == PERMA_TECHNIQUE_BOUNDED_BATCHES)
        st = parse_bounded(&c, &s);
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

/* The megakernel part after the technique: "/strategy[/victim][+localN]";
 * -1 for an unnamed strategy or victim. */
static int format_megakernel(const perma_schedule *s, char *buf, size_t size)
{
    const char *strategy = perma_strategy_name(s->strategy);
    const char *victim = steals(s->strategy) ? perma_victim_name(s->victim) : "";
    if (!strategy || !victim)
        return -1;
    char local[32] = "";
    if (s->local_queue_items)
        snprintf(local, sizeof local, "+local%u", s->local_queue_items);
    return snprintf(buf, size, "/%s%s%s%s", strategy, *victim ? "/" : "", victim, local);
}

int perma_schedule_format(const perma_schedule *s, char *buf, size_t size)
{
    const char *technique = perma_technique_name(s->technique);
    char rest[96] = "";
    int n = 0;
    if (technique && s->technique == PERMA_TECHNIQUE_MEGAKERNEL)
        n = format_megakernel(s, rest, sizeof rest);
    else if (s->technique == PERMA_TECHNIQUE_BOUNDED_BATCHES && s->batch_limit)
        n = snprintf(rest, sizeof rest, "/p=%u", s->batch_limit);
    if (!technique || n < 0) {
        if (size)
            buf[0] = '\0';
        return -1;
    }
    return snprintf(buf, size, "%s%s", technique, rest);
}
