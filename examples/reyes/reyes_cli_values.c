/*
 * The text of an option's value turned into numbers (whole numbers in a
 * range, finite floats, WxH sizes, comma-separated lists), and the message
 * of bad usage, for the option handlers (reyes_cli_options.c) and the
 * argument walk (reyes_cli.c).
 */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_cli_internal.h"

int cli_usage_error(char *message, size_t size, const char *format, const char *a, const char *b)
{
    snprintf(message, size, format, a, b);
    return REYES_CLI_USAGE;
}

int cli_parse_unsigned(const char *text, unsigned long max, unsigned *out)
{
    if (!isdigit((unsigned char)text[0])) /* strtoul would skip spaces and take a sign */
        return 0;
    char *end;
    errno = 0;
    unsigned long value = strtoul(text, &end, 10);
    if (errno || *end || value > max)
        return 0;
    *out = (unsigned)value;
    return 1;
}

int cli_parse_float(const char *text, float *out)
{
    char *end;
    errno = 0;
    float value = strtof(text, &end);
    /* Overflow is an infinity (refused); underflow (ERANGE) is a tiny number. */
    if (!text[0] || *end || !isfinite(value))
        return 0;
    *out = value;
    return 1;
}

/* "WxH" with both sides in 1..REYES_MAX_SIZE; 0 if malformed. */
int cli_parse_wxh(const char *value, unsigned *w, unsigned *h)
{
    char width[32], height[32];
    const char *x = strchr(value, 'x');
    size_t n = x ? (size_t)(x - value) : 0;
    if (!x || n >= sizeof width || strlen(x + 1) >= sizeof height)
        return 0;
    memcpy(width, value, n);
    width[n] = '\0';
    strcpy(height, x + 1);
    return cli_parse_unsigned(width, REYES_MAX_SIZE, w) && *w > 0
           && cli_parse_unsigned(height, REYES_MAX_SIZE, h) && *h > 0;
}

/* Parse exactly `count` comma-separated numbers of `option` into out[];
 * `shape` shows the expected form in the message (e.g. "dx,dy,dz"). */
int cli_parse_float_list(const char *option, const char *value, float *out, int count, const char *shape,
                         char *message, size_t size)
{
    char what[64];
    const char *at = value;
    for (int k = 0; k < count; ++k) {
        char number[64];
        size_t n = strcspn(at, ",");
        int last = k == count - 1;
        if (n == 0 || n >= sizeof number || (last ? at[n] != '\0' : at[n] != ',')) {
            snprintf(what, sizeof what, "%s '%%s': expected %d numbers %%s", option, count);
            return cli_usage_error(message, size, what, value, shape);
        }
        memcpy(number, at, n);
        number[n] = '\0';
        if (!cli_parse_float(number, &out[k])) {
            snprintf(what, sizeof what, "%s: '%%s' is not a number%%s", option);
            return cli_usage_error(message, size, what, number, "");
        }
        at += n + (last ? 0 : 1);
    }
    return REYES_CLI_OK;
}
