/* Result rows: a readable table on stdout, printed as rows finish, and the
 * same rows as CSV.  The ratio column is sequential C time / row time, so
 * above 1 means faster than sequential C. */
#include "bench.h"

#include <stdlib.h>
#include <string.h>

struct bench_report {
    const char *benchmark;
    perma_output *csv_output; /* written whole at the end, or not at all */
    FILE *csv;
    double baseline_seconds; /* sequential C time of the current workload */
    double baseline_cpu;     /* and its CPU time */
    int show_cpu;            /* print the "cpu vs seq" column */
    unsigned failures;
    unsigned perma_measured;     /* perma rows that ran (they carry a group size) */
    char first_skip[96];         /* why the first row that did not run did not */
    int width;               /* of the variant column: wider for " @DEVICE" names */
};

void bench_row_init(bench_row *row, const char *workload, const char *variant, const char *unit)
{
    memset(row, 0, sizeof *row);
    snprintf(row->workload, sizeof row->workload, "%s", workload);
    snprintf(row->variant, sizeof row->variant, "%s", variant);
    row->unit = unit;
    bench_status_show(workload, variant);
    bench_activity("measuring %s (%s)", variant, workload);
}

int bench_report_open(bench_report **out, const char *benchmark, const bench_options *options)
{
    bench_report *r = calloc(1, sizeof *r);
    if (!r) {
        fprintf(stderr, "perma-bench: out of memory\n");
        return 1;
    }
    r->benchmark = benchmark;
    r->width = options->device_count ? 44 : 36;
    if (options->csv_path) {
        perma_error error;
        if (perma_output_open(options->csv_path, &r->csv_output, &error) != PERMA_OK) {
            fprintf(stderr, "perma-bench: --csv: %s\n", error.message);
            free(r);
            return 1;
        }
        r->csv = perma_output_stream(r->csv_output);
        fprintf(r->csv, "benchmark,workload,variant,group_size,work_groups,status,seconds,wall_seconds,"
                        "units,unit,rate,speedup_vs_sequential,count,expected,check,peak_queue_bytes,"
                        "peak_item_bytes,steals,donations,spills,message,cpu_seconds\n");
    }
    *out = r;
    return 0;
}

void bench_report_widen(bench_report *r, int extra)
{
    r->width += extra;
}

void bench_report_show_cpu(bench_report *r)
{
    r->show_cpu = 1;
}

static const char *check_name(bench_check check)
{
    return check == BENCH_CHECK_PASS ? "ok" : check == BENCH_CHECK_FAIL ? "WRONG" : "-";
}

/* 1234567 -> "1.23M" style, for the table. */
static void human(char *out, size_t size, double value)
{
    if (value >= 1e9)
        snprintf(out, size, "%.2fG", value / 1e9);
    else if (value >= 1e6)
        snprintf(out, size, "%.2fM", value / 1e6);
    else if (value >= 1e3)
        snprintf(out, size, "%.1fk", value / 1e3);
    else
        snprintf(out, size, "%.0f", value);
}

static void print_header(const bench_report *r)
{
    printf("%-*s %4s %3s %9s %9s %8s%s %6s %9s %9s  %s\n", r->width, "variant", "gs", "wg", "seconds", "rate/s",
           "vs seq", r->show_cpu ? " cpu vs seq" : "", "check", "peak q.B", "items B", "note");
}

void bench_report_workload(bench_report *r, const char *title)
{
    r->baseline_seconds = 0.0;
    printf("\n== %s: %s ==\n", r->benchmark, title);
    print_header(r);
    fflush(stdout);
}

/* A quoted CSV field with no quote, comma or newline inside, so that
 * simple tools (awk -F, in plot.sh) can split the lines. */
static void csv_text(FILE *f, const char *text)
{
    fputc('"', f);
    for (const char *p = text; *p; ++p)
        fputc(*p == '"' ? '\'' : *p == '\n' ? ' ' : *p == ',' ? ';' : *p, f);
    fputc('"', f);
}

/* The first line of a message, at most 90 characters, for the table. */
static void short_note(char *out, size_t size, const char *message)
{
    size_t n = strcspn(message, "\n");
    if (n > 90)
        n = 90;
    if (n >= size)
        n = size - 1;
    memcpy(out, message, n);
    out[n] = '\0';
}

void bench_report_add(bench_report *r, const bench_row *row, int is_baseline)
{
    char note[96];
    short_note(note, sizeof note, row->message);
    if (is_baseline && row->ran) {
        r->baseline_seconds = row->seconds;
        r->baseline_cpu = row->cpu_seconds;
    }
    if (row->check == BENCH_CHECK_FAIL)
        ++r->failures;
    if (row->ran && row->group_size)
        ++r->perma_measured;
    if (!row->ran && !r->first_skip[0])
        snprintf(r->first_skip, sizeof r->first_skip, "%s", note[0] ? note : row->variant);
    bench_status_row_printed();
    double rate = row->ran && row->seconds > 0 ? row->units / row->seconds : 0.0;
    double ratio = row->ran && row->seconds > 0 && r->baseline_seconds > 0 ? r->baseline_seconds / row->seconds : 0.0;

    char gs[16] = "-", wg[16] = "-", rate_text[16], peak[16] = "-", items[16] = "-";
    if (row->group_size)
        snprintf(gs, sizeof gs, "%u", row->group_size);
    if (row->work_groups)
        snprintf(wg, sizeof wg, "%u", row->work_groups);
    if (row->peak_queue_bytes)
        human(peak, sizeof peak, (double)row->peak_queue_bytes);
    if (row->peak_item_bytes)
        human(items, sizeof items, (double)row->peak_item_bytes);
    /* CPU time of sequential C / the row's: the share of the CPU time a
     * row spends on the work itself. */
    char cpu_text[16] = "";
    if (r->show_cpu) {
        double cpu = row->ran && row->cpu_seconds > 0 && r->baseline_cpu > 0 ? r->baseline_cpu / row->cpu_seconds : 0.0;
        char value[16] = "-";
        if (cpu > 0)
            snprintf(value, sizeof value, "%.2fx", cpu);
        snprintf(cpu_text, sizeof cpu_text, " %10s", value);
    }
    if (!row->ran) {
        printf("%-*s %4s %3s %9s %9s %8s%s %6s %9s %9s  %s\n", r->width, row->variant, gs, wg, "n/a", "n/a", "n/a",
               cpu_text, "-", "-", "-", note);
    } else {
        human(rate_text, sizeof rate_text, rate);
        char ratio_text[16] = "-";
        if (ratio > 0)
            snprintf(ratio_text, sizeof ratio_text, "%.2fx", ratio);
        printf("%-*s %4s %3s %9.4f %9s %8s%s %6s %9s %9s  %s\n", r->width, row->variant, gs, wg, row->seconds, rate_text,
               ratio_text, cpu_text, check_name(row->check), peak, items, note);
    }
    fflush(stdout);

    if (!r->csv)
        return;
    fprintf(r->csv, "%s,", r->benchmark);
    csv_text(r->csv, row->workload);
    fputc(',', r->csv);
    csv_text(r->csv, row->variant);
    fprintf(r->csv, ",%u,%u,%s,%.6f,%.6f,%.0f,%s,%.1f,%.4f,%llu,%llu,%s,%zu,%zu,%llu,%llu,%llu,", row->group_size,
            row->work_groups, row->ran ? "ok" : "n/a", row->seconds, row->wall_seconds, row->units,
            row->unit ? row->unit : "", rate, ratio, (unsigned long long)row->count,
            (unsigned long long)row->expected, check_name(row->check), row->peak_queue_bytes,
            row->peak_item_bytes, (unsigned long long)row->steals, (unsigned long long)row->donations,
            (unsigned long long)row->spills);
    csv_text(r->csv, row->message);
    fprintf(r->csv, ",%.6f\n", row->cpu_seconds);
}

unsigned bench_report_failures(const bench_report *r)
{
    return r->failures;
}

int bench_report_close(bench_report *r)
{
    int failed = 0;
    if (r->failures)
        printf("\n%u row(s) produced a WRONG result\n", r->failures);
    /* A run that measured no perma variant is a failure, not an empty success. */
    if (!r->perma_measured) {
        fprintf(stderr, "perma-bench %s: nothing was measured: no perma variant ran%s%s%s\n", r->benchmark,
                r->first_skip[0] ? " (the first row that did not: " : "", r->first_skip,
                r->first_skip[0] ? ")" : "");
        failed = 1;
    }
    perma_error error;
    if (r->csv_output && perma_output_commit(r->csv_output, &error) != PERMA_OK) {
        fprintf(stderr, "perma-bench: --csv: %s\n", error.message);
        failed = 1;
    }
    free(r);
    return failed;
}
