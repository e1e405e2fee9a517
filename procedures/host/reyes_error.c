/* Error values of the Reyes library. */
#include <stdarg.h>
#include <stdio.h>

#include "reyes.h"

reyes_status reyes_fail(reyes_error *error, reyes_status status, const char *format, ...)
{
    if (error) {
        va_list args;
        va_start(args, format);
        vsnprintf(error->message, sizeof error->message, format, args);
        va_end(args);
        error->status = status;
    }
    return status;
}
