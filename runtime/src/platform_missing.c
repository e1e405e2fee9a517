/* Why the ICD loader found no OpenCL platform: no driver is registered, or
 * the registered drivers could not be loaded (a broken installation, or a
 * memory limit too small for the driver's libraries). */
#include "device.h"
#include "device_list.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MIB ((size_t)1 << 20)

static bool is_icd(const char *name)
{
    size_t n = strlen(name);
    return n > 4 && strcmp(name + n - 4, ".icd") == 0;
}

/* The drivers registered where the ICD loader looks (OCL_ICD_VENDORS, a
 * directory or one file, else /etc/OpenCL/vendors): their count, and the
 * first names in `names`. */
static unsigned registered_drivers(const char **where, char *names, size_t size)
{
    const char *vendors = getenv("OCL_ICD_VENDORS");
    *where = vendors && *vendors ? vendors : "/etc/OpenCL/vendors";
    names[0] = '\0';
    struct stat st;
    if (stat(*where, &st) != 0)
        return 0;
    if (!S_ISDIR(st.st_mode)) {
        snprintf(names, size, "%s", *where);
        return 1;
    }
    DIR *dir = opendir(*where);
    if (!dir)
        return 0;
    unsigned count = 0;
    size_t used = 0;
    for (struct dirent *e; (e = readdir(dir)) != NULL;) {
        if (!is_icd(e->d_name))
            continue;
        if (count < 4 && used < size)
            used += (size_t)snprintf(names + used, size - used, "%s%s", count ? ", " : "", e->d_name);
        ++count;
    }
    closedir(dir);
    return count;
}

void perma_no_platform_message(char *out, size_t size)
{
    const char *where;
    char names[256];
    unsigned drivers = registered_drivers(&where, names, sizeof names);
    if (drivers == 0) {
        snprintf(out, size, "no OpenCL platform found; install an OpenCL driver, e.g. "
                            "'apt-get install pocl-opencl-icd'");
        return;
    }
    char why[256] = "OCL_ICD_DEBUG=7 shows why";
    perma_headroom h;
    if (perma_memory_headroom(&h))
        snprintf(why, sizeof why, "the process's %s of %zu MiB (%zu MiB free) may be too small for the "
                 "driver's libraries", h.name, h.limit / MIB, h.free / MIB);
    snprintf(out, size, "no OpenCL platform could be loaded, though %u driver%s %s registered in %s (%s); %s",
             drivers, drivers == 1 ? "" : "s", drivers == 1 ? "is" : "are", where, names, why);
}
