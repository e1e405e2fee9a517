/* The host's half of the host/device ABI checks (kernels/perma_abi.h):
 * static assertions that the host's structs put each member at the word
 * index the kernels use, the compile-time checks the generated program
 * makes of the device's sizes and offsets, and the sentence for a build
 * log in which one of those failed. */
#include "abi.h"
#include "internal.h"
#include "state.h"
#include "strbuf.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define ASSERT_MEMBER(type, member, word) \
    _Static_assert(offsetof(type, member) == 4 * (word), #type "." #member " is not at word " #word);
#define ASSERT_STRUCT(type, words) _Static_assert(sizeof(type) == 4 * (words), #type " is not " #words " words");
PERMA_ABI_MEMBERS(ASSERT_MEMBER)
PERMA_ABI_STRUCTS(ASSERT_STRUCT)
_Static_assert(PERMA_OVERFLOW_MAX_RECORDS == PERMA_MAX_EMITS + PERMA_MAX_PROCEDURES,
               "an emit area holds a batch's overflowed edges and one record per procedure");
_Static_assert(PERMA_OVERFLOW_RECORD(PERMA_OVERFLOW_MAX_RECORDS) <= PERMA_EMIT_AREA_HEADER,
               "the emit area's header holds PERMA_OVERFLOW_MAX_RECORDS records");
_Static_assert(offsetof(perma_ctl_block, queues) == 4 * PERMA_CTL_HEADER_WORDS,
               "the queue records follow the control block header");

/* The pseudo-files the checks are compiled under: a failed check's line
 * number in the compiler's message says which one it was. */
#define STRUCT_CHECKS_FILE "perma-abi-checks"
#define ITEM_CHECKS_FILE "perma-item-size-checks"
#define ELEMENT_CHECKS_FILE "perma-buffer-element-checks"

/* One layout fact: sizeof(type) (member NULL) or offsetof(type, member) on
 * the host, in bytes. */
typedef struct layout_fact {
    const char *type;
    const char *member;
    size_t bytes;
} layout_fact;

#define STRUCT_FACT(type, words) { #type, NULL, sizeof(type) },
#define MEMBER_FACT(type, member, word) { #type, #member, offsetof(type, member) },
static const layout_fact facts[] = { PERMA_ABI_STRUCTS(STRUCT_FACT) PERMA_ABI_MEMBERS(MEMBER_FACT) };
#define FACT_COUNT (sizeof facts / sizeof facts[0])

/* The checks suppress clang's note that repeating a typedef with the same
 * type is a C11 feature: the repetition is the point. */
static void begin_checks(perma_strbuf *sb, const char *file)
{
    perma_strbuf_printf(sb, "#pragma clang diagnostic push\n"
                            "#pragma clang diagnostic ignored \"-Wtypedef-redefinition\"\n"
                            "#line 1 \"%s\"\n", file);
}

static void end_checks(perma_strbuf *sb)
{
    perma_strbuf_append(sb, "#pragma clang diagnostic pop\n");
}

/* Line i + 1 of STRUCT_CHECKS_FILE checks facts[i].  Offsets are checked
 * plus one (an array of zero bytes is not C). */
void perma_abi_append_struct_checks(perma_strbuf *sb)
{
    begin_checks(sb, STRUCT_CHECKS_FILE);
    for (size_t i = 0; i < FACT_COUNT; ++i) {
        const layout_fact *f = &facts[i];
        if (f->member)
            perma_strbuf_printf(sb, "PERMA_ABI_CHECK(perma_abi_offset_of_%s_%s, %zu, PERMA_ABI_OFFSETOF(%s, %s) + 1)\n",
                                f->type, f->member, f->bytes + 1, f->type, f->member);
        else
            perma_strbuf_printf(sb, "PERMA_ABI_CHECK(perma_abi_size_of_%s, %zu, sizeof(%s))\n", f->type, f->bytes,
                                f->type);
    }
    end_checks(sb);
}

/* Line i + 1 of ITEM_CHECKS_FILE checks procedure i's item_size. */
void perma_abi_append_item_checks(const perma_runtime *rt, perma_strbuf *sb)
{
    begin_checks(sb, ITEM_CHECKS_FILE);
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        const perma_proc_info *p = &rt->procs[i];
        perma_strbuf_printf(sb, "PERMA_ABI_CHECK(perma_item_size_of_%s, %zu, sizeof(%s))\n", p->name, p->item_size,
                            p->item_type);
    }
    end_checks(sb);
}

/* Line b + 1 of ELEMENT_CHECKS_FILE checks the element size of buffer b,
 * if it was bound with one (perma_bind_host_array). */
void perma_abi_append_element_checks(const perma_runtime *rt, perma_strbuf *sb)
{
    bool any = false;
    for (unsigned b = 0; b < rt->buffer_count; ++b)
        any = any || rt->buffers[b].element_size != 0;
    if (!any)
        return;
    begin_checks(sb, ELEMENT_CHECKS_FILE);
    for (unsigned b = 0; b < rt->buffer_count; ++b) {
        const perma_buffer_binding *binding = &rt->buffers[b];
        if (binding->element_size)
            perma_strbuf_printf(sb, "PERMA_ABI_CHECK(perma_element_size_of_%s, %zu, sizeof(%s))\n", binding->name,
                                binding->element_size, binding->element_type);
        else
            perma_strbuf_append(sb, "\n");
    }
    end_checks(sb);
}

/* In `line`, the check number after "FILE:" and the two sizes of
 * "'char[DEVICE]' vs 'char[HOST]'"; false if the line has not all three. */
static bool parse_failed_check(const char *line, const char *file, unsigned *check, unsigned long *device,
                               unsigned long *host)
{
    const char *at = strstr(line, file);
    const char *types = strstr(line, "'char[");
    if (!at || !types || at[strlen(file)] != ':')
        return false;
    char *end;
    *check = (unsigned)strtoul(at + strlen(file) + 1, &end, 10);
    if (end == at + strlen(file) + 1)
        return false;
    return sscanf(types, "'char[%lu]' vs 'char[%lu]'", device, host) == 2;
}

bool perma_abi_explain_log(const perma_runtime *rt, const char *log, char *out, size_t size)
{
    for (const char *line = log, *newline; *line; line = newline ? newline + 1 : line + strlen(line)) {
        newline = strchr(line, '\n');
        char text[512];
        size_t length = newline ? (size_t)(newline - line) : strlen(line);
        if (length >= sizeof text)
            length = sizeof text - 1;
        memcpy(text, line, length);
        text[length] = '\0';
        unsigned check;
        unsigned long device, host;
        if (parse_failed_check(text, ITEM_CHECKS_FILE, &check, &device, &host) && check >= 1 &&
            check <= rt->proc_count) {
            const perma_proc_info *p = &rt->procs[check - 1];
            snprintf(out, size, "procedure '%s': item_size is %zu bytes, but sizeof(%s) is %lu bytes on the device "
                                "(.item_size must be the size of the item type as the device compiles it)",
                     p->name, p->item_size, p->item_type, device);
            return true;
        }
        if (parse_failed_check(text, ELEMENT_CHECKS_FILE, &check, &device, &host) && check >= 1 &&
            check <= rt->buffer_count) {
            const perma_buffer_binding *b = &rt->buffers[check - 1];
            snprintf(out, size, "buffer '%s': its host elements are %zu bytes (PERMA_BIND_HOST_ARRAY), but "
                                "sizeof(%s) is %lu bytes on the device (declare the type alike on both sides, "
                                "and mind float3 and alignment)",
                     b->name, b->element_size, b->element_type, device);
            return true;
        }
        if (parse_failed_check(text, STRUCT_CHECKS_FILE, &check, &device, &host) && check >= 1 &&
            check <= FACT_COUNT) {
            const layout_fact *f = &facts[check - 1];
            if (f->member)
                snprintf(out, size, "the device puts %s.%s at byte %lu, the host at byte %lu (kernels/perma_abi.h): "
                                    "this OpenCL compiler lays out the shared structs differently",
                         f->type, f->member, device - 1, host - 1);
            else
                snprintf(out, size, "sizeof(%s) is %lu bytes on the device, %lu on the host (kernels/perma_abi.h): "
                                    "this OpenCL compiler lays out the shared structs differently",
                         f->type, device, host);
            return true;
        }
    }
    return false;
}
