/*
 * The values of the command-line engine: an option's text parsed into its
 * target by the row's kind (whole numbers, numbers, WxH, one of a list of
 * names), what a row accepts said in words, and number lists for the
 * programs' own parsers.
 */
#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include <perma.h>

#include "perma_cli_internal.h"

/* CHOICE rows write the index as an unsigned into perma's enums too. */
_Static_assert(sizeof(perma_technique) == sizeof(unsigned) && sizeof(perma_strategy) == sizeof(unsigned) &&
               sizeof(perma_victim) == sizeof(unsigned), "perma's enums are unsigned-sized");

const char *perma_cli_technique_name(unsigned value)
{
    return perma_technique_name((perma_technique)value);
}

const char *perma_cli_strategy_name(unsigned value)
{
    return perma_strategy_name((perma_strategy)value);
}

const char *perma_cli_victim_name(unsigned value)
{
    return perma_victim_name((perma_victim)value);
}

const char *perma_cli_choice_name(const perma_cli_option *option, unsigned k)
{
    if (option->name_of)
        return option->name_of(k);
    for (unsigned i = 0; i < k; ++i) /* a NULL-terminated list: do not read past its end */
        if (!option->names[i])
            return NULL;
    return option->names[k];
}

/* A whole decimal number in least..most: no sign, space or other text
 * (strtoull would skip spaces and take a sign). */
static int parse_whole(const char *text, unsigned long long least, unsigned long long most, unsigned long long *out)
{
    if (!isdigit((unsigned char)text[0]))
        return 0;
    char *end;
    errno = 0;
    unsigned long long value = strtoull(text, &end, 10);
    if (errno || *end || value < least || value > most)
        return 0;
    *out = value;
    return 1;
}

/* Whether a number is within the row's bounds; a FLOAT row compares in
 * float, so that "--epsilon 0.01" meets a bound of 0.01 (0.01f < 0.01). */
static int within(const perma_cli_option *o, double value)
{
    double low = o->kind == PERMA_CLI_KIND_FLOAT ? (float)o->low : o->low;
    double high = o->kind == PERMA_CLI_KIND_FLOAT ? (float)o->high : o->high;
    int above = o->open & PERMA_CLI_ABOVE_LOW ? value > low : value >= low;
    int below = o->open & PERMA_CLI_BELOW_HIGH ? value < high : value <= high;
    return above && below;
}

/* A whole text that is a finite number, into *(float *)out (strtof: no
 * double rounding) or *(double *)out. */
static int parse_number(const char *text, int is_float, void *out)
{
    char *end;
    double value = is_float ? strtof(text, &end) : strtod(text, &end);
    if (!text[0] || *end || !isfinite(value))
        return 0;
    float narrow = (float)value; /* exact: value came from strtof */
    memcpy(out, is_float ? (void *)&narrow : (void *)&value, is_float ? sizeof narrow : sizeof value);
    return 1;
}

/* "WxH" with both sides in least..most. */
static int parse_size(const char *text, unsigned long long least, unsigned long long most, unsigned out[2])
{
    char width[32];
    const char *x = strchr(text, 'x');
    size_t n = x ? (size_t)(x - text) : 0;
    unsigned long long w, h;
    if (!x || n >= sizeof width)
        return 0;
    memcpy(width, text, n);
    width[n] = '\0';
    if (!parse_whole(width, least, most, &w) || !parse_whole(x + 1, least, most, &h))
        return 0;
    out[0] = (unsigned)w;
    out[1] = (unsigned)h;
    return 1;
}

static int parse_choice(const perma_cli_option *o, const char *text)
{
    for (unsigned k = 0; perma_cli_choice_name(o, k); ++k) {
        if (strcmp(perma_cli_choice_name(o, k), text) == 0) {
            memcpy(o->target, &k, sizeof k);
            return 1;
        }
    }
    return 0;
}

/* Parse `text` into the row's target; 0 if it is not a value the row takes. */
static int parse_value(const perma_cli_option *o, const char *text)
{
    unsigned long long whole;
    switch (o->kind) {
    case PERMA_CLI_KIND_FLAG:
        *(int *)o->target = 1;
        return 1;
    case PERMA_CLI_KIND_TEXT:
        *(const char **)o->target = text;
        return 1;
    case PERMA_CLI_KIND_WHOLE:
        if (o->most > UINT_MAX || !parse_whole(text, o->least, o->most, &whole))
            return 0;
        *(unsigned *)o->target = (unsigned)whole;
        return 1;
    case PERMA_CLI_KIND_WHOLE64:
        return parse_whole(text, o->least, o->most, (unsigned long long *)o->target);
    case PERMA_CLI_KIND_FLOAT: {
        float value;
        if (!parse_number(text, 1, &value) || !within(o, value))
            return 0;
        *(float *)o->target = value;
        return 1;
    }
    case PERMA_CLI_KIND_DOUBLE: {
        double value;
        if (!parse_number(text, 0, &value) || !within(o, value))
            return 0;
        *(double *)o->target = value;
        return 1;
    }
    case PERMA_CLI_KIND_SIZE:
        return parse_size(text, o->least, o->most, (unsigned *)o->target);
    case PERMA_CLI_KIND_CHOICE:
        return parse_choice(o, text);
    case PERMA_CLI_KIND_CUSTOM:
        break;
    }
    return 0;
}

int perma_cli_apply(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    if (option->kind == PERMA_CLI_KIND_CUSTOM)
        return option->parse(option, value, complaint, size);
    if (parse_value(option, value))
        return 0;
    char accepted[PERMA_CLI_MESSAGE_MAX];
    perma_cli_accepted(option, 0, accepted, sizeof accepted);
    snprintf(complaint, size, "expected %s", accepted);
    return 1;
}

/* A bound as %g writes it, its exponent without '+' and leading zeros
 * ("1e6", not "1e+06"). */
static const char *bound(double value, char out[32])
{
    snprintf(out, 32, "%g", value);
    char *e = strchr(out, 'e');
    if (e) {
        char *digits = e + 1 + (e[1] == '+' || e[1] == '-');
        size_t zeros = strspn(digits, "0");
        memmove(e[1] == '+' ? e + 1 : digits, digits + zeros, strlen(digits + zeros) + 1);
    }
    return out;
}

/* "L..H", or the bounds that hold ("> 0.5 and < 179", ">= 0"); "" if none. */
static void bounds_text(const perma_cli_option *o, char *out, size_t size)
{
    char low[32], high[32];
    const char *above = o->open & PERMA_CLI_ABOVE_LOW ? ">" : ">=";
    const char *below = o->open & PERMA_CLI_BELOW_HIGH ? "<" : "<=";
    int has_low = isfinite(o->low), has_high = isfinite(o->high);
    if (has_low && has_high && !o->open)
        snprintf(out, size, " in %s..%s", bound(o->low, low), bound(o->high, high));
    else if (has_low && has_high)
        snprintf(out, size, " %s %s and %s %s", above, bound(o->low, low), below, bound(o->high, high));
    else if (has_low)
        snprintf(out, size, " %s %s", above, bound(o->low, low));
    else if (has_high)
        snprintf(out, size, " %s %s", below, bound(o->high, high));
    else
        out[0] = '\0';
}

/* "a, b or c". */
static void names_text(const perma_cli_option *o, char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (unsigned k = 0; perma_cli_choice_name(o, k) && used < size; ++k) {
        const char *separator = k == 0 ? "" : perma_cli_choice_name(o, k + 1) ? ", " : " or ";
        int n = snprintf(out + used, size - used, "%s%s", separator, perma_cli_choice_name(o, k));
        used += n > 0 ? (size_t)n : 0;
    }
}

void perma_cli_accepted(const perma_cli_option *o, int for_help, char *out, size_t size)
{
    char part[PERMA_CLI_MESSAGE_MAX];
    const char *what = o->argument ? o->argument : "";
    out[0] = '\0';
    switch (o->kind) {
    case PERMA_CLI_KIND_WHOLE:
    case PERMA_CLI_KIND_WHOLE64: {
        unsigned long long full = o->kind == PERMA_CLI_KIND_WHOLE ? UINT_MAX : ULLONG_MAX;
        if (o->least == 0 && o->most == full)
            snprintf(out, size, "%s", for_help ? "" : "a whole number");
        else
            snprintf(out, size, "%s in %llu..%llu", for_help ? what : "a whole number", o->least, o->most);
        break;
    }
    case PERMA_CLI_KIND_FLOAT:
    case PERMA_CLI_KIND_DOUBLE:
        bounds_text(o, part, sizeof part);
        if (!for_help)
            snprintf(out, size, "a number%s", part);
        else if (part[0])
            snprintf(out, size, "%s%s", what, part);
        break;
    case PERMA_CLI_KIND_SIZE:
        snprintf(out, size, "%ssides in %llu..%llu", for_help ? "" : "WxH with ", o->least, o->most);
        break;
    case PERMA_CLI_KIND_CHOICE:
        names_text(o, part, sizeof part);
        snprintf(out, size, "%s%s%s", for_help ? what : "", for_help ? ": " : "", part);
        break;
    case PERMA_CLI_KIND_FLAG:
    case PERMA_CLI_KIND_TEXT:
    case PERMA_CLI_KIND_CUSTOM:
        break;
    }
}

int perma_cli_value_text(const perma_cli_option *option, char *out, size_t size)
{
    if (option->kind == PERMA_CLI_KIND_FLAG) {
        snprintf(out, size, "%s", *(const int *)option->target ? "on" : "off");
        return 1;
    }
    if (option->kind == PERMA_CLI_KIND_CHOICE) {
        unsigned value;
        memcpy(&value, option->target, sizeof value);
        const char *name = perma_cli_choice_name(option, value);
        snprintf(out, size, "%s", name ? name : "?");
        return 1;
    }
    return 0;
}

/* Exactly `count` comma-separated numbers into out[] (floats or doubles). */
static int parse_list(const char *text, void *out, int is_float, size_t count, const char *shape, char *complaint,
                      size_t size)
{
    const char *at = text;
    for (size_t k = 0; k < count; ++k) {
        char number[64];
        size_t n = strcspn(at, ",");
        int last = k + 1 == count;
        if (n == 0 || n >= sizeof number || (last ? at[n] != '\0' : at[n] != ',')) {
            snprintf(complaint, size, "expected %zu numbers %s", count, shape);
            return 1;
        }
        memcpy(number, at, n);
        number[n] = '\0';
        size_t stride = is_float ? sizeof(float) : sizeof(double);
        if (!parse_number(number, is_float, (char *)out + k * stride)) {
            /* Digits all read, yet not finite: too large for the type. */
            char *end;
            const char *digits = number + (number[0] == '+' || number[0] == '-');
            strtod(number, &end);
            if (!*end && (isdigit((unsigned char)*digits) || *digits == '.'))
                snprintf(complaint, size, "'%s' is out of range: numbers here are at most +-%g", number,
                         is_float ? (double)FLT_MAX : DBL_MAX);
            else
                snprintf(complaint, size, "'%s' is not a number", number);
            return 1;
        }
        at += n + (last ? 0 : 1);
    }
    return 0;
}

int perma_cli_floats(const char *text, float *out, size_t count, const char *shape, char *complaint, size_t size)
{
    return parse_list(text, out, 1, count, shape, complaint, size);
}

int perma_cli_doubles(const char *text, double *out, size_t count, const char *shape, char *complaint, size_t size)
{
    return parse_list(text, out, 0, count, shape, complaint, size);
}
