/* Device lists: parsing "P:D", "NAME:D", "P:D/N", "P:D/N.K" and "all", and
 * expanding a list into device references checked against the installed
 * platforms. */
#include "device.h"
#include "device_list.h"
#include "internal.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* A decimal number of at most 7 digits at text[*at..end); advances *at. */
static bool parse_number(const char *text, size_t *at, size_t end, long *out)
{
    size_t start = *at;
    long value = 0;
    while (*at < end && isdigit((unsigned char)text[*at]) && *at - start < 7)
        value = value * 10 + (text[(*at)++] - '0');
    if (*at == start || (*at < end && isdigit((unsigned char)text[*at])))
        return false;
    *out = value;
    return true;
}

bool perma_platform_name_valid(const char *text, size_t length)
{
    if (length == 0 || length >= sizeof ((perma_device_entry *)0)->name || !isalpha((unsigned char)text[0])
        || (length == 3 && strncmp(text, "all", 3) == 0))
        return false;
    for (size_t i = 0; i < length; ++i)
        if (!isalnum((unsigned char)text[i]) && !strchr(" ()._-", text[i]))
            return false;
    return true;
}

static bool contains_ignoring_case(const char *text, const char *part)
{
    size_t n = strlen(part);
    for (; *text; ++text) {
        size_t i = 0;
        while (i < n && tolower((unsigned char)text[i]) == tolower((unsigned char)part[i]))
            ++i;
        if (i == n)
            return true;
    }
    return false;
}

int perma_platform_find(const cl_platform_id *platforms, cl_uint count, const char *name, char *listing,
                        size_t size)
{
    size_t used = 0;
    if (size)
        listing[0] = '\0';
    for (cl_uint p = 0; p < count; ++p) {
        char platform[128] = "", vendor[128] = "";
        clGetPlatformInfo(platforms[p], CL_PLATFORM_NAME, sizeof platform - 1, platform, NULL);
        clGetPlatformInfo(platforms[p], CL_PLATFORM_VENDOR, sizeof vendor - 1, vendor, NULL);
        if (contains_ignoring_case(platform, name) || contains_ignoring_case(vendor, name))
            return (int)p;
        int n = used < size ? snprintf(listing + used, size - used, "%s%u '%s' (%s)", p ? ", " : "",
                                       (unsigned)p, platform, vendor) : 0;
        if (n > 0)
            used += (size_t)n;
    }
    return -1;
}

bool perma_device_entry_parse(const char *text, size_t length, perma_device_entry *out)
{
    perma_device_entry e = { .all = false, .name = "", .platform = 0, .device = 0, .parts = 0, .part = -1 };
    if (length == 3 && strncmp(text, "all", 3) == 0) {
        e.all = true;
        *out = e;
        return true;
    }
    size_t at = 0;
    long p = 0, d = 0, n = 0, k = -1;
    if (isalpha((unsigned char)text[0])) {
        /* NAME, NAME:D, NAME/N, NAME:D/N.K ... */
        size_t name_length = 0;
        while (name_length < length && text[name_length] != ':' && text[name_length] != '/')
            ++name_length;
        if (!perma_platform_name_valid(text, name_length))
            return false;
        memcpy(e.name, text, name_length);
        e.name[name_length] = '\0';
        at = name_length;
        if (at < length && text[at] == ':' && (++at, !parse_number(text, &at, length, &d)))
            return false;
    } else if (!parse_number(text, &at, length, &p) || at >= length || text[at++] != ':'
               || !parse_number(text, &at, length, &d)) {
        return false;
    }
    if (at < length) {
        if (text[at++] != '/' || !parse_number(text, &at, length, &n) || n < 1
            || n > (long)PERMA_MAX_SUB_DEVICES)
            return false;
        if (at < length && (text[at++] != '.' || !parse_number(text, &at, length, &k) || k >= n))
            return false;
        if (at != length)
            return false;
    }
    e.platform = (int)p;
    e.device = (int)d;
    /* "/1" is the device itself: one part of all its compute units. */
    e.parts = n >= 2 ? (unsigned)n : 0;
    e.part = n >= 2 ? (int)k : -1;
    *out = e;
    return true;
}

bool perma_device_list_first(const char *list, perma_device_entry *first, size_t *bad_offset,
                             size_t *bad_length)
{
    size_t at = 0;
    bool have_first = false;
    for (;;) {
        size_t length = strcspn(list + at, ",");
        perma_device_entry e;
        if (!perma_device_entry_parse(list + at, length, &e)) {
            *bad_offset = at;
            *bad_length = length;
            return false;
        }
        if (!have_first) {
            *first = e;
            have_first = true;
        }
        if (list[at + length] == '\0')
            return true;
        at += length + 1;
    }
}

static perma_status fail(perma_error *error, perma_status status, const char *format, ...)
    __attribute__((format(printf, 3, 4)));

static perma_status fail(perma_error *error, perma_status status, const char *format, ...)
{
    if (error) {
        va_list ap;
        va_start(ap, format);
        error->status = status;
        vsnprintf(error->message, sizeof error->message, format, ap);
        va_end(ap);
    }
    return status;
}

/* The installed platforms and, per platform, its devices. */
typedef struct device_table {
    cl_uint platform_count;
    cl_platform_id platforms[64];
    cl_uint device_count[64];
    cl_device_id devices[64][64];
} device_table;

static perma_status load_table(device_table *t, perma_error *error)
{
    char message[PERMA_MESSAGE_MAX];
    if (!perma_memory_driver_fits(message, sizeof message, false))
        return fail(error, PERMA_ERR_NO_MEMORY, "%s", message);
    cl_int err = clGetPlatformIDs(0, NULL, &t->platform_count);
    if (err == -1001 /* CL_PLATFORM_NOT_FOUND_KHR */ || (err == CL_SUCCESS && t->platform_count == 0)) {
        perma_no_platform_message(message, sizeof message);
        return fail(error, PERMA_ERR_NO_PLATFORM, "%s", message);
    }
    if (err != CL_SUCCESS)
        return fail(error, PERMA_ERR_OPENCL, "clGetPlatformIDs failed: %s (%d)",
                    perma_cl_error_name(err), (int)err);
    if (t->platform_count > 64)
        t->platform_count = 64;
    clGetPlatformIDs(t->platform_count, t->platforms, NULL);
    for (cl_uint p = 0; p < t->platform_count; ++p) {
        cl_uint n = 0;
        if (clGetDeviceIDs(t->platforms[p], CL_DEVICE_TYPE_ALL, 0, NULL, &n) != CL_SUCCESS)
            n = 0;
        t->device_count[p] = n > 64 ? 64 : n;
        if (t->device_count[p])
            clGetDeviceIDs(t->platforms[p], CL_DEVICE_TYPE_ALL, t->device_count[p], t->devices[p], NULL);
    }
    return PERMA_OK;
}

bool perma_device_splits_equally(cl_device_id device, unsigned parts, char *why, size_t why_size)
{
    cl_uint units = 0, most = 0;
    cl_device_partition_property props[16];
    size_t size = 0;
    clGetDeviceInfo(device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof units, &units, NULL);
    if (clGetDeviceInfo(device, CL_DEVICE_PARTITION_MAX_SUB_DEVICES, sizeof most, &most, NULL) != CL_SUCCESS)
        most = 0;
    if (clGetDeviceInfo(device, CL_DEVICE_PARTITION_PROPERTIES, sizeof props, props, &size) != CL_SUCCESS)
        size = 0;
    bool equally = false;
    for (size_t i = 0; i < size / sizeof props[0]; ++i)
        equally = equally || props[i] == CL_DEVICE_PARTITION_EQUALLY;
    if (!equally) {
        snprintf(why, why_size, "does not support equal partitions (clCreateSubDevices with "
                                "CL_DEVICE_PARTITION_EQUALLY)");
        return false;
    }
    if (parts > units || parts > most) {
        snprintf(why, why_size, "has %u compute units and at most %u sub-devices: cannot split it "
                                "into %u equal sub-devices", (unsigned)units, (unsigned)most, parts);
        return false;
    }
    return true;
}

static perma_status add(perma_device_ref *out, unsigned max, unsigned *count, const char *list,
                        perma_device_ref ref, perma_error *error)
{
    char label[64];
    perma_device_ref_format(&ref, label, sizeof label);
    for (unsigned i = 0; i < *count; ++i)
        if (memcmp(&out[i], &ref, sizeof ref) == 0)
            return fail(error, PERMA_ERR_ARGUMENT, "device list '%s': device %s appears twice", list, label);
    if (*count >= max)
        return fail(error, PERMA_ERR_ARGUMENT, "device list '%s': more than %u devices", list, max);
    out[(*count)++] = ref;
    return PERMA_OK;
}

/* Append the devices of entry e of `list`. */
static perma_status expand(const device_table *t, const perma_device_entry *named, const char *list,
                           perma_device_ref *out, unsigned max, unsigned *count, perma_error *error)
{
    perma_status st = PERMA_OK;
    perma_device_entry resolved = *named;
    const perma_device_entry *e = &resolved;
    if (named->name[0]) {
        char listing[PERMA_MESSAGE_MAX / 2];
        resolved.platform = perma_platform_find(t->platforms, t->platform_count, named->name, listing,
                                                sizeof listing);
        if (resolved.platform < 0)
            return fail(error, PERMA_ERR_NO_DEVICE, "device list '%s': no OpenCL platform's name or vendor "
                        "contains '%s'; the platforms are: %s", list, named->name, listing);
    }
    if (e->all) {
        for (cl_uint p = 0; p < t->platform_count && st == PERMA_OK; ++p)
            for (cl_uint d = 0; d < t->device_count[p] && st == PERMA_OK; ++d)
                st = add(out, max, count, list, (perma_device_ref){ (int)p, (int)d, 0, 0 }, error);
        return st;
    }
    if ((cl_uint)e->platform >= t->platform_count)
        return fail(error, PERMA_ERR_NO_DEVICE, "device list '%s': OpenCL platform %d requested, but "
                    "only %u platform(s) exist", list, e->platform, (unsigned)t->platform_count);
    if ((cl_uint)e->device >= t->device_count[e->platform])
        return fail(error, PERMA_ERR_NO_DEVICE, "device list '%s': OpenCL device %d:%d requested, but "
                    "platform %d has %u device(s)", list, e->platform, e->device, e->platform,
                    (unsigned)t->device_count[e->platform]);
    if (e->parts == 0)
        return add(out, max, count, list, (perma_device_ref){ e->platform, e->device, 0, 0 }, error);
    char why[256];
    if (!perma_device_splits_equally(t->devices[e->platform][e->device], e->parts, why, sizeof why))
        return fail(error, PERMA_ERR_NO_DEVICE, "device list '%s': OpenCL device %d:%d %s", list,
                    e->platform, e->device, why);
    unsigned first = e->part < 0 ? 0 : (unsigned)e->part;
    unsigned last = e->part < 0 ? e->parts - 1 : (unsigned)e->part;
    for (unsigned k = first; k <= last && st == PERMA_OK; ++k)
        st = add(out, max, count, list, (perma_device_ref){ e->platform, e->device, e->parts, k }, error);
    return st;
}

perma_status perma_device_list(const char *list, perma_device_ref *out, unsigned max, unsigned *count,
                               perma_error *error)
{
    if (error) {
        error->status = PERMA_OK;
        error->message[0] = '\0';
    }
    if (!out || !count)
        return fail(error, PERMA_ERR_ARGUMENT, "perma_device_list: out or count is NULL");
    *count = 0;
    char env[PERMA_SETTING_MAX];
    if (!list || !*list) {
        list = perma_settings_device(env, sizeof env);
        if (!list || !*list)
            list = "0:0";
    }
    perma_device_entry first;
    size_t bad_offset, bad_length;
    if (!perma_device_list_first(list, &first, &bad_offset, &bad_length))
        return fail(error, PERMA_ERR_ARGUMENT, "device list '%s': entry '%.*s' is not of the form %s",
                    list, (int)bad_length, list + bad_offset, PERMA_DEVICE_FORMS);
    device_table *table = malloc(sizeof *table);
    if (!table)
        return fail(error, PERMA_ERR_NO_MEMORY, "out of memory listing devices");
    perma_status st = load_table(table, error);
    for (size_t at = 0; st == PERMA_OK;) {
        size_t length = strcspn(list + at, ",");
        perma_device_entry e;
        perma_device_entry_parse(list + at, length, &e); /* checked above */
        st = expand(table, &e, list, out, max, count, error);
        if (list[at + length] == '\0')
            break;
        at += length + 1;
    }
    free(table);
    if (st != PERMA_OK)
        *count = 0;
    return st;
}

int perma_device_ref_format(const perma_device_ref *ref, char *buf, size_t size)
{
    if (ref->sub_devices >= 2)
        return snprintf(buf, size, "%d:%d/%u.%u", ref->platform_index, ref->device_index,
                        ref->sub_devices, ref->sub_device);
    return snprintf(buf, size, "%d:%d", ref->platform_index, ref->device_index);
}

void perma_config_set_device(perma_config *config, const perma_device_ref *ref)
{
    config->platform_index = ref->platform_index;
    config->device_index = ref->device_index;
    config->sub_devices = ref->sub_devices >= 2 ? ref->sub_devices : 0;
    config->sub_device = ref->sub_devices >= 2 ? ref->sub_device : 0;
}
