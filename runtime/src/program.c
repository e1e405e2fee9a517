/* Compiling the generated megakernel. */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

void perma_release_program(perma_runtime *rt)
{
    cl_kernel *kernels[] = { &rt->kernel, &rt->step_kernel, &rt->take_kernel };
    for (size_t i = 0; i < 3; ++i) {
        if (*kernels[i])
            clReleaseKernel(*kernels[i]);
        *kernels[i] = NULL;
    }
    if (rt->program)
        clReleaseProgram(rt->program);
    rt->program = NULL;
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

static perma_status report_build_failure(perma_runtime *rt, cl_int code)
{
    size_t size = 0;
    clGetProgramBuildInfo(rt->program, rt->device, CL_PROGRAM_BUILD_LOG, 0, NULL, &size);
    char *log = calloc(1, size + 1);
    if (!log)
        return perma_set_error(rt, PERMA_ERR_BUILD, "clBuildProgram failed (%s) and the log is too large",
                               perma_cl_error_name(code));
    clGetProgramBuildInfo(rt->program, rt->device, CL_PROGRAM_BUILD_LOG, size, log, NULL);
    if (getenv("PERMA_BUILD_LOG"))
        fprintf(stderr, "perma: build log:\n%s\n", log);
    char summary[PERMA_MESSAGE_MAX - 64];
    summarize_log(log, summary, sizeof summary);
    free(log);
    return perma_set_error(rt, PERMA_ERR_BUILD, "building the megakernel failed:\n%s", summary);
}

/* PoCL compiles a kernel for real at its first launch with a local size:
 * launch each kernel the technique uses once on an empty state (no item
 * outstanding, so every group leaves at once), so perma_build pays for the
 * compile rather than the first perma_run. */
static perma_status warm_up(perma_runtime *rt)
{
    unsigned queues = rt->queue_sets * rt->proc_count;
    size_t ctl_words = perma_ctl_words(queues, rt->work_groups);
    size_t stats_words = (size_t)rt->work_groups * perma_stat_group_words(rt->proc_count, rt->max_edges);
    perma_status st = perma_ensure_buffer(rt, &rt->ctl_mem, &(size_t){ 0 }, ctl_words, "control block");
    size_t stats_have = 0, data_have = rt->data_mem_words;
    if (st == PERMA_OK)
        st = perma_ensure_buffer(rt, &rt->stats_mem, &stats_have, stats_words, "statistics");
    if (st == PERMA_OK)
        st = perma_ensure_buffer(rt, &rt->data_mem, &data_have, 1, "queue items");
    if (st != PERMA_OK)
        return st;
    rt->data_mem_words = data_have;
    cl_uint zero = 0;
    PERMA_CL_CHECK(rt, "clEnqueueFillBuffer (warm-up control block)",
                   clEnqueueFillBuffer(rt->queue, rt->ctl_mem, &zero, sizeof zero, 0, ctl_words * 4, 0, NULL, NULL));
    size_t local = rt->group_size;
    if (rt->config.technique == PERMA_TECHNIQUE_MEGAKERNEL) {
        __atomic_store_n(rt->abort_flag, 0u, __ATOMIC_SEQ_CST);
        st = perma_set_common_args(rt, rt->kernel, PERMA_MEGAKERNEL_USER_ARG);
        if (st != PERMA_OK)
            return st;
        size_t global = (size_t)rt->work_groups * local;
        PERMA_CL_CHECK(rt, "clEnqueueNDRangeKernel (warm-up)",
                       clEnqueueNDRangeKernel(rt->queue, rt->kernel, 1, NULL, &global, &local, 0, NULL, NULL));
    } else {
        st = perma_warm_up_steps(rt);
        if (st != PERMA_OK)
            return st;
    }
    PERMA_CL_CHECK(rt, "clFinish (warm-up)", clFinish(rt->queue));
    return PERMA_OK;
}

perma_status perma_build(perma_runtime *rt)
{
    if (!rt)
        return PERMA_ERR_ARGUMENT;
    if (rt->built)
        return PERMA_OK;
    perma_release_program(rt);
    perma_status st = perma_build_layout(rt);
    if (st != PERMA_OK)
        return st;

    perma_strbuf sb;
    perma_strbuf_init(&sb);
    st = perma_generate_program(rt, &sb);
    if (st != PERMA_OK) {
        perma_strbuf_free(&sb);
        return st;
    }
    const char *dump = getenv("PERMA_DUMP_PROGRAM");
    if (dump && *dump) {
        FILE *f = fopen(dump, "w");
        if (f) {
            fputs(sb.data, f);
            fclose(f);
        }
    }
    cl_int err;
    const char *text = sb.data;
    rt->program = clCreateProgramWithSource(rt->context, 1, &text, NULL, &err);
    perma_strbuf_free(&sb);
    PERMA_CL_CHECK(rt, "clCreateProgramWithSource", err);

    char options[1024];
    snprintf(options, sizeof options, "-cl-std=CL1.2 %s%s", rt->debug ? "-DPERMA_DEBUG=1 " : "",
             rt->config.build_options ? rt->config.build_options : "");
    err = clBuildProgram(rt->program, 1, &rt->device, options, NULL, NULL);
    if (err == CL_BUILD_PROGRAM_FAILURE || err == CL_INVALID_BUILD_OPTIONS) {
        st = report_build_failure(rt, err);
        perma_release_program(rt);
        return st;
    }
    if (err != CL_SUCCESS) {
        perma_release_program(rt);
        PERMA_CL_CHECK(rt, "clBuildProgram", err);
    }
    static const char *const names[] = { "perma_megakernel", "perma_step_kernel", "perma_take_kernel" };
    cl_kernel *kernels[] = { &rt->kernel, &rt->step_kernel, &rt->take_kernel };
    for (size_t i = 0; i < 3; ++i) {
        *kernels[i] = clCreateKernel(rt->program, names[i], &err);
        if (err != CL_SUCCESS) {
            perma_release_program(rt);
            return perma_set_error(rt, PERMA_ERR_OPENCL, "clCreateKernel(%s) failed: %s (%d)", names[i],
                                   perma_cl_error_name(err), (int)err);
        }
    }
    st = warm_up(rt);
    if (st != PERMA_OK) {
        perma_release_program(rt);
        return st;
    }
    rt->built = true;
    rt->message[0] = '\0';
    return PERMA_OK;
}
