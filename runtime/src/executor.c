/* The one place that maps a technique to the code that runs it. */
#include "steps.h"

const perma_executor *perma_executor_for(perma_technique technique)
{
    static const perma_executor *const executors[] = {
        &perma_megakernel_executor,
        &perma_kernel_per_procedure_executor.executor,
        &perma_bounded_batches_executor.executor,
    };
    for (size_t i = 0; i < sizeof executors / sizeof executors[0]; ++i)
        if (executors[i]->technique == technique)
            return executors[i];
    return NULL;
}
