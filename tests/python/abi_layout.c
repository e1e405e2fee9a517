/* The sizes and field offsets of perma.h's structures as JSON, for the test
 * that the Python binding's ctypes mirrors of them (runtime/python/perma/
 * _capi.py) match the C compiler's layout (test_abi.py).  A field added to
 * a structure changes its size here, so the test fails until _capi.py and
 * this list name it too.  With --enums: the values of perma.h's enums that
 * _capi.py mirrors. */
#include <perma.h>

#include <stddef.h>
#include <stdio.h>
#include <string.h>

static int first_struct = 1, first_field;

#define STRUCT(T)                                                                              \
    printf("%s\n  \"%s\": {\"size\": %zu, \"fields\": {", first_struct ? "{" : "}},", #T, sizeof(T)); \
    first_struct = 0;                                                                          \
    first_field = 1
#define FIELD(T, F)                                                                            \
    printf("%s\"%s\": %zu", first_field ? "" : ", ", #F, offsetof(T, F));                      \
    first_field = 0

static int enums(void)
{
#define ENUM(V, LAST) printf("  \"%s\": %d%s\n", #V, (int)(V), (LAST) ? "" : ",")
    printf("{\n");
    ENUM(PERMA_SCHEDULES_ALL, 0); ENUM(PERMA_SCHEDULES_VICTIMS_ONCE, 0); ENUM(PERMA_SCHEDULES_DEFAULT_VICTIM, 0);
    ENUM(PERMA_REDUCE_SUM, 0); ENUM(PERMA_REDUCE_MIN, 0); ENUM(PERMA_REDUCE_MAX, 0);
    ENUM(PERMA_TYPE_UINT, 0); ENUM(PERMA_TYPE_INT, 0); ENUM(PERMA_TYPE_ULONG, 0); ENUM(PERMA_TYPE_LONG, 0);
    ENUM(PERMA_TYPE_FLOAT, 0); ENUM(PERMA_TYPE_DOUBLE, 1);
    printf("}\n");
#undef ENUM
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "--enums") == 0)
        return enums();
    STRUCT(perma_error);
    FIELD(perma_error, status); FIELD(perma_error, message);
    STRUCT(perma_schedule);
    FIELD(perma_schedule, technique); FIELD(perma_schedule, strategy); FIELD(perma_schedule, victim);
    FIELD(perma_schedule, local_queue_items); FIELD(perma_schedule, batch_limit);
    FIELD(perma_schedule, donation_threshold); FIELD(perma_schedule, work_first_items);
    STRUCT(perma_config);
    FIELD(perma_config, platform_index); FIELD(perma_config, device_index); FIELD(perma_config, platform_name);
    FIELD(perma_config, sub_devices); FIELD(perma_config, sub_device); FIELD(perma_config, work_groups);
    FIELD(perma_config, group_size); FIELD(perma_config, items_per_work_item); FIELD(perma_config, queue_capacity);
    FIELD(perma_config, queue_memory_limit); FIELD(perma_config, time_limit); FIELD(perma_config, stall_limit);
    FIELD(perma_config, local_memory_limit); FIELD(perma_config, build_options); FIELD(perma_config, build_log);
    FIELD(perma_config, build_log_user); FIELD(perma_config, schedule);
    FIELD(perma_config, trace_path); FIELD(perma_config, trace_events); FIELD(perma_config, progress);
    FIELD(perma_config, progress_user); FIELD(perma_config, progress_interval);
    STRUCT(perma_device_ref);
    FIELD(perma_device_ref, platform_index); FIELD(perma_device_ref, device_index);
    FIELD(perma_device_ref, sub_devices); FIELD(perma_device_ref, sub_device);
    STRUCT(perma_emit);
    FIELD(perma_emit, target); FIELD(perma_emit, max_items);
    STRUCT(perma_procedure);
    FIELD(perma_procedure, name); FIELD(perma_procedure, item_type); FIELD(perma_procedure, item_size);
    FIELD(perma_procedure, threads_per_item); FIELD(perma_procedure, local_bytes_per_item);
    FIELD(perma_procedure, source); FIELD(perma_procedure, source_file); FIELD(perma_procedure, function);
    FIELD(perma_procedure, emits); FIELD(perma_procedure, priority); FIELD(perma_procedure, cooperative);
    FIELD(perma_procedure, queue_only);
    STRUCT(perma_procedure_stats);
    FIELD(perma_procedure_stats, name); FIELD(perma_procedure_stats, items); FIELD(perma_procedure_stats, batches);
    FIELD(perma_procedure_stats, emitted); FIELD(perma_procedure_stats, emit_count);
    FIELD(perma_procedure_stats, seeded); FIELD(perma_procedure_stats, peak_queue_items);
    FIELD(perma_procedure_stats, initial_capacity); FIELD(perma_procedure_stats, queue_capacity);
    FIELD(perma_procedure_stats, regrowths); FIELD(perma_procedure_stats, batch_size);
    FIELD(perma_procedure_stats, batch_cut); FIELD(perma_procedure_stats, batch_cut_emit);
    FIELD(perma_procedure_stats, stacked_items);
    STRUCT(perma_group_stats);
    FIELD(perma_group_stats, batches); FIELD(perma_group_stats, items); FIELD(perma_group_stats, steals);
    FIELD(perma_group_stats, donations); FIELD(perma_group_stats, donated_items); FIELD(perma_group_stats, spills);
    FIELD(perma_group_stats, idle_polls); FIELD(perma_group_stats, stacked_items);
    FIELD(perma_group_stats, stack_spills); FIELD(perma_group_stats, stack_peak);
    STRUCT(perma_stats);
    FIELD(perma_stats, seconds); FIELD(perma_stats, launches); FIELD(perma_stats, regrowths);
    FIELD(perma_stats, work_groups); FIELD(perma_stats, group_size); FIELD(perma_stats, procedure_count);
    FIELD(perma_stats, peak_queue_bytes); FIELD(perma_stats, queue_memory_limit); FIELD(perma_stats, queues_kept);
    FIELD(perma_stats, items); FIELD(perma_stats, steals); FIELD(perma_stats, donations);
    FIELD(perma_stats, spills); FIELD(perma_stats, idle_polls); FIELD(perma_stats, overflowed_items);
    FIELD(perma_stats, technique); FIELD(perma_stats, strategy); FIELD(perma_stats, stacked_items);
    FIELD(perma_stats, stack_spills); FIELD(perma_stats, stack_peak); FIELD(perma_stats, stack_items);
    FIELD(perma_stats, work_groups_reason); FIELD(perma_stats, resident_groups); FIELD(perma_stats, kernel_local_bytes);
    printf("}}\n}\n");
    return 0;
}
