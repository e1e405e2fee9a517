/* Compiling the generated megakernel. */
#include "abi.h"
#include "barriers.h"
#include "build_log.h"
#include "clock.h"
#include "codegen.h"
#include "executor.h"
#include "layout.h"
#include "program.h"
#include "program_cache.h"
#include "reductions.h"
#include "state.h"
#include "strbuf.h"

#include <stdlib.h>
#include <string.h>

/* The kernels of every generated program, by name. */
static const char *const kernel_names[] = { "perma_megakernel", "perma_step_kernel", "perma_take_kernel",
                                            "perma_relayout_kernel" };
#define KERNEL_COUNT (sizeof kernel_names / sizeof kernel_names[0])

static void kernel_slots(perma_runtime *rt, cl_kernel *slots[KERNEL_COUNT])
{
    slots[0] = &rt->build.kernel;
    slots[1] = &rt->build.step_kernel;
    slots[2] = &rt->build.take_kernel;
    slots[3] = &rt->build.relayout_kernel;
}

void perma_release_program(perma_runtime *rt)
{
    cl_kernel *kernels[KERNEL_COUNT];
    kernel_slots(rt, kernels);
    for (size_t i = 0; i < KERNEL_COUNT; ++i) {
        if (*kernels[i])
            clReleaseKernel(*kernels[i]);
        *kernels[i] = NULL;
    }
    if (rt->build.program)
        clReleaseProgram(rt->build.program);
    rt->build.program = NULL;
}

/* Keep the lines of a build log that say what is wrong, within the message. */
static void summarize_log(const char *log, char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    const char *line = log;
    for (int pass = 0; pass < 2 && used == 0; ++pass) {
        for (line = log; *line;) {
            const char *end = strchr(line, '\n');
            size_t len = end ? (size_t)(end - line) : strlen(line);
            bool wanted = pass == 1 || strstr(line, "error") != NULL;
            if (wanted && len > 0 && used + len + 2 < size) {
                memcpy(out + used, line, len);
                used += len;
                out[used++] = '\n';
                out[used] = '\0';
            }
            line = end ? end + 1 : line + len;
        }
    }
    if (used > 0 && out[used - 1] == '\n')
        out[used - 1] = '\0';
}

/* The program's build log ("" if there is none); NULL if out of memory. */
static char *read_build_log(perma_runtime *rt)
{
    size_t size = 0;
    if (clGetProgramBuildInfo(rt->build.program, rt->device, CL_PROGRAM_BUILD_LOG, 0, NULL, &size) != CL_SUCCESS)
        size = 0;
    char *log = calloc(1, size + 1);
    if (log && size)
        clGetProgramBuildInfo(rt->build.program, rt->device, CL_PROGRAM_BUILD_LOG, size, log, NULL);
    return log;
}

/* Show the warnings of a build that succeeded (build_log.c); returns how
 * many. */
static unsigned report_build_warnings(perma_runtime *rt)
{
    char *log = read_build_log(rt);
    unsigned warnings = log ? perma_build_log_show(rt, log, false) : 0;
    free(log);
    return warnings;
}

static perma_status report_build_failure(perma_runtime *rt, cl_int code)
{
    char *log = read_build_log(rt);
    if (!log)
        return perma_set_error(rt, PERMA_ERR_BUILD, "clBuildProgram failed (%s) and the log is too large",
                               perma_cl_error_name(code));
    perma_build_log_show(rt, log, true);
    char summary[PERMA_MESSAGE_MAX - 64];
    if (!perma_abi_explain_log(rt, log, summary, sizeof summary) &&
        !perma_barriers_explain_log(rt, log, summary, sizeof summary))
        summarize_log(log, summary, sizeof summary);
    free(log);
    return perma_set_error(rt, PERMA_ERR_BUILD, "building the megakernel failed:\n%s", summary);
}

/* PoCL compiles a kernel for real at its first launch with a local size:
 * launch each kernel the technique uses once on an empty state (no item
 * outstanding, so every group leaves at once), so perma_build pays for the
 * compile rather than the first perma_run.  (perma_relayout_kernel is
 * compiled at the first regrowth, which most runs never reach.) */
static perma_status warm_up(perma_runtime *rt)
{
    perma_status st = perma_state_empty(rt);
    if (st == PERMA_OK)
        st = rt->executor->warm_up(rt);
    if (st != PERMA_OK)
        return st;
    cl_int err = clFinish(rt->queue);
    return err == CL_SUCCESS ? PERMA_OK : perma_cl_error(rt, "clFinish (warm-up)", err);
}

/* After clCreateProgramWithSource and clBuildProgram (or the cache): the
 * error of a call that failed, with the log for a failed build; the
 * program is then released. */
static perma_status check_build(perma_runtime *rt, cl_int err)
{
    if (!rt->build.program && err != CL_SUCCESS)
        return perma_cl_error(rt, "clCreateProgramWithSource", err);
    if (err == CL_BUILD_PROGRAM_FAILURE || err == CL_INVALID_BUILD_OPTIONS) {
        perma_status st = report_build_failure(rt, err);
        perma_release_program(rt);
        return st;
    }
    if (err != CL_SUCCESS) {
        perma_release_program(rt);
        return perma_cl_error(rt, "clBuildProgram", err);
    }
    return PERMA_OK;
}

/* rt->build.program for the generated `text`: from the disk cache
 * (program_cache.c), else built from source.  A miss takes the entry's
 * build lock first, which waits while another process builds the same
 * program, and looks again: a farm's ranks compile it once.  The lock is
 * held until perma_build stores the program after its warm-up launch
 * (the caller closes the entry this opens). */
static perma_status build_program(perma_runtime *rt, const char *text, const char *options,
                                  perma_cache_entry *entry)
{
    cl_int err = CL_SUCCESS;
    perma_cache_entry_open(rt, text, options, entry);
    rt->build.program = perma_cache_load(rt, entry, options);
    if (!rt->build.program && perma_cache_lock(entry))
        rt->build.program = perma_cache_load(rt, entry, options);
    rt->build.info.wait_seconds = entry->waited;
    rt->build.info.origin = rt->build.program ? PERMA_PROGRAM_CACHED : PERMA_PROGRAM_COMPILED;
    if (!rt->build.program) {
        rt->build.program = clCreateProgramWithSource(rt->context, 1, &text, NULL, &err);
        if (err == CL_SUCCESS)
            err = clBuildProgram(rt->build.program, 1, &rt->device, options, NULL, NULL);
    }
    return check_build(rt, err);
}

static perma_status create_kernels(perma_runtime *rt)
{
    cl_int err;
    cl_kernel *kernels[KERNEL_COUNT];
    kernel_slots(rt, kernels);
    for (size_t i = 0; i < KERNEL_COUNT; ++i) {
        *kernels[i] = clCreateKernel(rt->build.program, kernel_names[i], &err);
        if (err != CL_SUCCESS)
            return perma_set_error(rt, PERMA_ERR_OPENCL, "clCreateKernel(%s) failed: %s (%d)", kernel_names[i],
                                   perma_cl_error_name(err), (int)err);
    }
    return PERMA_OK;
}

/* The program, its kernels and their compile at the first launch (PoCL),
 * all in rt->build.info.seconds; a program compiled here without warnings
 * is stored after that launch, by the CPU time all of it took (waiting for
 * another process's build costs none).  *rebuild: the kernel made the
 * runtime lower its work-group count (device.c), on which the program
 * may depend; it is released (and not warmed up). */
static perma_status build_and_warm_up(perma_runtime *rt, const char *text, const char *options, bool *rebuild)
{
    double start = perma_now(), cpu_start = perma_cpu_now();
    memset(&rt->build.info, 0, sizeof rt->build.info);
    *rebuild = false;
    perma_cache_entry entry;
    perma_status st = build_program(rt, text, options, &entry);
    /* A program with warnings is not cached, so that every build shows them. */
    bool warned = st == PERMA_OK && report_build_warnings(rt) != 0;
    if (st == PERMA_OK)
        st = create_kernels(rt);
    if (st == PERMA_OK)
        st = perma_work_groups_fit(rt, rebuild);
    if (st == PERMA_OK && !*rebuild)
        st = warm_up(rt);
    rt->build.info.seconds = perma_now() - start;
    double cpu_seconds = perma_cpu_now() - cpu_start;
    /* A program built for a count the kernel lowered is stored too: where
     * the count does not change the program (one queue set, staging that
     * the count does not cut), the next build loads it. */
    if (st == PERMA_OK && rt->build.info.origin == PERMA_PROGRAM_COMPILED && !warned)
        rt->build.info.stored = perma_cache_store(rt, &entry, cpu_seconds);
    if (st != PERMA_OK || *rebuild) {
        perma_release_program(rt);
        rt->build.info.origin = PERMA_PROGRAM_NOT_BUILT;
    }
    perma_cache_entry_close(&entry);
    return st;
}

/* The layout; with `plan`, at the work-group count it settles on a device
 * that is not a CPU (device.c): the count depends on the layout's __local
 * memory and the layout on the count (queue sets, staging). */
static perma_status lay_out(perma_runtime *rt, bool plan)
{
    perma_status st = perma_build_layout(rt);
    if (st == PERMA_OK && plan && perma_work_groups_plan(rt, rt->build.local_bytes))
        st = perma_build_layout(rt);
    return st;
}

/* One build: the layout (planning the count with `plan`), the generated
 * program, its compile. */
static perma_status build_once(perma_runtime *rt, bool plan, bool *rebuild)
{
    *rebuild = false;
    perma_release_program(rt);
    perma_status st = lay_out(rt, plan);
    if (st != PERMA_OK)
        return st;
    perma_strbuf sb, reduce_constants, reduce_helpers;
    perma_strbuf_init(&sb);
    perma_strbuf_init(&reduce_constants);
    perma_strbuf_init(&reduce_helpers);
    perma_reductions_generate(rt, &reduce_constants, &reduce_helpers);
    st = perma_generate_program(rt, &reduce_constants, &reduce_helpers, &sb);
    perma_strbuf_free(&reduce_constants);
    perma_strbuf_free(&reduce_helpers);
    if (st != PERMA_OK) {
        perma_strbuf_free(&sb);
        return st;
    }
    const char *dump = rt->settings.dump_program;
    if (*dump) {
        perma_output *out;
        perma_error ignored; /* a debugging aid: the build goes on without it */
        if (perma_output_open(dump, &out, &ignored) == PERMA_OK) {
            fputs(sb.data, perma_output_stream(out));
            perma_output_commit(out, &ignored);
        }
    }
    char options[1024];
    snprintf(options, sizeof options, "-cl-std=CL1.2 %s%s", rt->debug ? "-DPERMA_DEBUG=1 " : "",
             rt->config.build_options ? rt->config.build_options : "");
    st = build_and_warm_up(rt, sb.data, options, rebuild);
    perma_strbuf_free(&sb);
    return st;
}

/* Builds of one program at most: the first at the count the layout
 * plans, another at the count the compiled kernel allows if it holds fewer
 * groups (its registers, or more __local memory than the layout's figure),
 * one more to spare. */
#define BUILD_ATTEMPTS 3

perma_status perma_build_program(perma_runtime *rt)
{
    if (rt->built)
        return PERMA_OK;
    bool rebuild = true;
    perma_status st = PERMA_OK;
    for (unsigned attempt = 0; st == PERMA_OK && rebuild; ++attempt) {
        if (attempt == BUILD_ATTEMPTS)
            return perma_set_error(rt, PERMA_ERR_BUILD, "the megakernel did not settle on a work-group count "
                                   "in %u builds (now %u: %s)", BUILD_ATTEMPTS, rt->work_groups,
                                   rt->work_groups_reason);
        st = build_once(rt, attempt == 0, &rebuild);
    }
    if (st != PERMA_OK)
        return st;
    rt->built = true;
    rt->build.serial++; /* queue i may mean another queue now */
    rt->message[0] = '\0';
    return PERMA_OK;
}

static perma_status build_call(perma_runtime *rt)
{
    perma_status begun = perma_call_begin(rt, "perma_build", true);
    return begun == PERMA_OK ? perma_build_program(rt) : begun;
}

perma_status perma_build(perma_runtime *rt)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_build", build_call(rt));
}

static perma_status get_build_info_call(perma_runtime *rt, perma_build_info *out)
{
    if (!rt || !out)
        return PERMA_ERR_ARGUMENT;
    perma_call_begin(rt, "perma_get_build_info", false);
    *out = rt->build.info;
    return PERMA_OK;
}

perma_status perma_get_build_info(perma_runtime *rt, perma_build_info *out)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_get_build_info", get_build_info_call(rt, out));
}
