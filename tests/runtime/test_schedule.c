/*
 * Schedule labels (perma_schedule_parse/format): every label the
 * benchmarks, examples and tests use parses and formats back, a default
 * perma_config's schedule is megakernel/shared, and bad labels are
 * PERMA_ERR_ARGUMENT with a message naming the bad part; the donation
 * threshold (/d=N) only after a donating strategy.  No device is
 * needed.
 */
#include "perma_test.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Canonical labels: the benchmark tables (benchmarks/variants.c,
 * bench_reyes.c), the Reyes test schedules and the stress test. */
static const char *const canonical[] = {
    "megakernel/shared",
    "megakernel/stealing/random",
    "megakernel/stealing/round-robin",
    "megakernel/donation",
    "megakernel/stealing-donation/random",
    "megakernel/shared+local256",
    "megakernel/stealing/random+local256",
    "megakernel/shared+local64",
    "megakernel/shared+local32",
    "kernel-per-procedure",
    "bounded-batches",
    "bounded-batches/p=64",
    "bounded-batches/p=4096",
    "megakernel/donation/d=256",
    "megakernel/stealing-donation/random/d=1",
    "megakernel/stealing-donation/round-robin/d=64+local32",
    "megakernel/donation/d=4294967295",
    "megakernel/shared+wf32",
    "megakernel/stealing/random+local32+wf16",
    "megakernel/donation/d=64+wf4096",
    "megakernel/shared+wf0",
    "megakernel/stealing/random+local32+wf0",
};

/* Short forms in use (the stress test, the examples' --compare): the
 * victim of a stealing strategy defaults to random, the strategy to shared. */
static const struct {
    const char *label, *canonical;
} shorthand[] = {
    { "megakernel/stealing", "megakernel/stealing/random" },
    { "megakernel/stealing-donation", "megakernel/stealing-donation/random" },
    { "megakernel/stealing+local32", "megakernel/stealing/random+local32" },
    { "megakernel", "megakernel/shared" },
    { "megakernel+local8", "megakernel/shared+local8" },
    { "megakernel/stealing-donation/d=64", "megakernel/stealing-donation/random/d=64" },
    { "megakernel/stealing-donation/d=64+local32", "megakernel/stealing-donation/random/d=64+local32" },
    { "megakernel+wf16+local8", "megakernel/shared+local8+wf16" },
    { "megakernel/stealing+wf8", "megakernel/stealing/random+wf8" },
};

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

static void expect_format(const perma_schedule *s, const char *expected)
{
    char buf[128];
    int n = perma_schedule_format(s, buf, sizeof buf);
    ck_assert_str_eq(buf, expected);
    ck_assert_int_eq(n, (int)strlen(expected));
}

static perma_schedule parse_ok(const char *label)
{
    perma_schedule s;
    perma_error error;
    perma_status st = perma_schedule_parse(label, &s, &error);
    ck_assert_msg(st == PERMA_OK, "'%s': %s: %s", label, perma_status_name(st), error.message);
    ck_assert_int_eq(error.status, PERMA_OK);
    ck_assert_str_eq(error.message, "");
    return s;
}

START_TEST(canonical_labels_round_trip)
{
    for (size_t i = 0; i < COUNT(canonical); ++i) {
        perma_schedule s = parse_ok(canonical[i]);
        expect_format(&s, canonical[i]);
        perma_schedule again = parse_ok(canonical[i]);
        ck_assert(memcmp(&s, &again, sizeof s) == 0);
    }
}
END_TEST

START_TEST(short_forms_format_canonically)
{
    for (size_t i = 0; i < COUNT(shorthand); ++i) {
        perma_schedule s = parse_ok(shorthand[i].label);
        expect_format(&s, shorthand[i].canonical);
        perma_schedule canon = parse_ok(shorthand[i].canonical);
        ck_assert_msg(memcmp(&s, &canon, sizeof s) == 0, "'%s' and '%s' differ", shorthand[i].label,
                      shorthand[i].canonical);
    }
}
END_TEST

/* Labels and every field they set (the rest zero: the defaults). */
static const struct {
    const char *label;
    perma_schedule fields;
} parsed_fields[] = {
    { "megakernel/stealing-donation/round-robin+local32",
      { .technique = PERMA_TECHNIQUE_MEGAKERNEL, .strategy = PERMA_STRATEGY_STEALING_DONATION,
        .victim = PERMA_VICTIM_ROUND_ROBIN, .local_queue_items = 32 } },
    { "megakernel/stealing-donation/round-robin/d=64+local32",
      { .technique = PERMA_TECHNIQUE_MEGAKERNEL, .strategy = PERMA_STRATEGY_STEALING_DONATION,
        .victim = PERMA_VICTIM_ROUND_ROBIN, .local_queue_items = 32, .donation_threshold = 64 } },
    { "megakernel/donation/d=1",
      { .technique = PERMA_TECHNIQUE_MEGAKERNEL, .strategy = PERMA_STRATEGY_DONATION, .donation_threshold = 1 } },
    { "bounded-batches/p=64", { .technique = PERMA_TECHNIQUE_BOUNDED_BATCHES, .batch_limit = 64 } },
    { "kernel-per-procedure", { .technique = PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE } },
    { "megakernel/donation+local4096",
      { .technique = PERMA_TECHNIQUE_MEGAKERNEL, .strategy = PERMA_STRATEGY_DONATION,
        .local_queue_items = PERMA_MAX_LOCAL_QUEUE_ITEMS } },
};

START_TEST(parse_sets_every_field)
{
    for (size_t i = 0; i < sizeof parsed_fields / sizeof parsed_fields[0]; ++i) {
        const perma_schedule *want = &parsed_fields[i].fields;
        perma_schedule s = parse_ok(parsed_fields[i].label);
        ck_assert_msg(s.technique == want->technique && s.strategy == want->strategy && s.victim == want->victim
                          && s.local_queue_items == want->local_queue_items && s.batch_limit == want->batch_limit
                          && s.donation_threshold == want->donation_threshold,
                      "'%s' parsed to technique %d strategy %d victim %d local %u batch %u threshold %u",
                      parsed_fields[i].label, (int)s.technique, (int)s.strategy, (int)s.victim,
                      s.local_queue_items, s.batch_limit, s.donation_threshold);
    }
}
END_TEST

START_TEST(config_default_schedule_is_megakernel_shared)
{
    perma_config config;
    perma_config_init(&config);
    perma_schedule s = parse_ok("megakernel/shared");
    ck_assert(memcmp(&config.schedule, &s, sizeof s) == 0);
    char label[64];
    ck_assert_int_eq(perma_schedule_format(&config.schedule, label, sizeof label), (int)strlen("megakernel/shared"));
    ck_assert_str_eq(label, "megakernel/shared");
}
END_TEST

/* Labels that must fail, and their exact messages. */
static const struct {
    const char *label, *message;
} bad[] = {
    { "", "schedule '': empty label (e.g. megakernel/shared, kernel-per-procedure)" },
    { "megakernal/shared",
      "schedule 'megakernal/shared': unknown technique 'megakernal' (megakernel, kernel-per-procedure, "
      "bounded-batches)" },
    { "megakernel/stealng",
      "schedule 'megakernel/stealng': unknown strategy 'stealng' (shared, stealing, donation, "
      "stealing-donation)" },
    { "megakernel/", "schedule 'megakernel/': unknown strategy '' (shared, stealing, donation, "
      "stealing-donation)" },
    { "megakernel/stealing/rand",
      "schedule 'megakernel/stealing/rand': unknown victim 'rand' (random, round-robin)" },
    { "megakernel/shared/random",
      "schedule 'megakernel/shared/random': victim 'random' after strategy 'shared' (a victim only "
      "follows stealing or stealing-donation)" },
    { "kernel-per-procedure/shared",
      "schedule 'kernel-per-procedure/shared': '/shared' after kernel-per-procedure (a strategy is only "
      "valid with megakernel)" },
    { "bounded-batches/stealing",
      "schedule 'bounded-batches/stealing': strategy 'stealing' with bounded-batches (a strategy is only "
      "valid with megakernel)" },
    { "kernel-per-procedure+local32",
      "schedule 'kernel-per-procedure+local32': '+local32' after kernel-per-procedure (+localN and +wfN "
      "are only valid with megakernel)" },
    { "megakernel/shared+local",
      "schedule 'megakernel/shared+local': '+local' needs a number of items >= 1, e.g. +local32 (leave "
      "it out for no local queue)" },
    { "megakernel/shared+local0",
      "schedule 'megakernel/shared+local0': '+local0' needs a number of items >= 1, e.g. +local32 (leave "
      "it out for no local queue)" },
    { "megakernel/shared+local32x",
      "schedule 'megakernel/shared+local32x': '+local32x' needs a number of items >= 1, e.g. +local32 "
      "(leave it out for no local queue)" },
    { "megakernel/shared+local4294967296",
      "schedule 'megakernel/shared+local4294967296': '+local4294967296' needs a number of items >= 1, "
      "e.g. +local32 (leave it out for no local queue)" },
    { "megakernel/shared+local4097",
      "schedule 'megakernel/shared+local4097': '+local4097': at most 4096 items in a local queue" },
    { "megakernel/donation+local4294967295",
      "schedule 'megakernel/donation+local4294967295': '+local4294967295': at most 4096 items in a local "
      "queue" },
    { "megakernel/shared+queue4",
      "schedule 'megakernel/shared+queue4': unknown option '+queue4' (+localN: N items in a local "
      "queue; +wfN: work-first, a stack of N items per work-item, +wf0 none)" },
    { "megakernel/shared+wf",
      "schedule 'megakernel/shared+wf': '+wf' needs a number of items >= 1, e.g. +wf32 (leave it out for "
      "the default stack, +wf0 for none)" },
    { "megakernel/shared+wf00",
      "schedule 'megakernel/shared+wf00': '+wf00' needs a number of items >= 1, e.g. +wf32 (leave it out for "
      "the default stack, +wf0 for none)" },
    { "megakernel/shared+wf0+wf8",
      "schedule 'megakernel/shared+wf0+wf8': '+wf8' after another +wfN (give it once)" },
    { "megakernel/shared+wf4097",
      "schedule 'megakernel/shared+wf4097': '+wf4097': at most 4096 items on a work-item's stack" },
    { "megakernel/shared+wf8+wf8",
      "schedule 'megakernel/shared+wf8+wf8': '+wf8' after another +wfN (give it once)" },
    { "megakernel/shared+wfx",
      "schedule 'megakernel/shared+wfx': unknown option '+wfx' (+localN: N items in a local "
      "queue; +wfN: work-first, a stack of N items per work-item, +wf0 none)" },
    { "bounded-batches+wf8",
      "schedule 'bounded-batches+wf8': '+wf8' after bounded-batches (+localN and +wfN are only "
      "valid with megakernel)" },
    { "megakernel/shared+local32/x", "schedule 'megakernel/shared+local32/x': unexpected '/x' at the end" },
    { "megakernel/stealing/random/x",
      "schedule 'megakernel/stealing/random/x': unexpected '/x' at the end" },
    { "megakernel/shared+local32+local64",
      "schedule 'megakernel/shared+local32+local64': '+local64' after another +localN (give it once)" },
    { "megakernel/shared ", "schedule 'megakernel/shared ': unknown strategy 'shared ' (shared, stealing, "
      "donation, stealing-donation)" },
    { "bounded-batches/p=0",
      "schedule 'bounded-batches/p=0': '/p=0' needs a number of items >= 1, e.g. /p=64 (leave it out for "
      "the default)" },
    { "bounded-batches/p=",
      "schedule 'bounded-batches/p=': '/p=' needs a number of items >= 1, e.g. /p=64 (leave it out for "
      "the default)" },
    { "bounded-batches/q=4",
      "schedule 'bounded-batches/q=4': unknown option '/q=4' (bounded-batches takes /p=N: at most N "
      "items per host iteration)" },
    { "bounded-batches/p=64/x", "schedule 'bounded-batches/p=64/x': unexpected '/x' at the end" },
    /* The donation threshold: only after a donating strategy, once, N >= 1. */
    { "megakernel/stealing/d=4",
      "schedule 'megakernel/stealing/d=4': option '/d=4' after strategy 'stealing' (/d=N only follows "
      "donation or stealing-donation)" },
    { "megakernel/stealing/round-robin/d=4",
      "schedule 'megakernel/stealing/round-robin/d=4': option '/d=4' after strategy 'stealing' (/d=N only "
      "follows donation or stealing-donation)" },
    { "megakernel/d=4",
      "schedule 'megakernel/d=4': option '/d=4' after strategy 'shared' (/d=N only follows donation or "
      "stealing-donation)" },
    { "megakernel/donation/d=0",
      "schedule 'megakernel/donation/d=0': '/d=0' needs a number of items >= 1, e.g. /d=64 (leave it out "
      "for the default)" },
    { "megakernel/donation/d=junk",
      "schedule 'megakernel/donation/d=junk': '/d=junk' needs a number of items >= 1, e.g. /d=64 (leave it "
      "out for the default)" },
    { "megakernel/donation/d=",
      "schedule 'megakernel/donation/d=': '/d=' needs a number of items >= 1, e.g. /d=64 (leave it out "
      "for the default)" },
    { "megakernel/donation/d=4294967296",
      "schedule 'megakernel/donation/d=4294967296': '/d=4294967296' needs a number of items >= 1, e.g. "
      "/d=64 (leave it out for the default)" },
    { "megakernel/donation/d=8/d=16",
      "schedule 'megakernel/donation/d=8/d=16': '/d=16' after another /d=N (give it once)" },
    { "megakernel/donation/x=3",
      "schedule 'megakernel/donation/x=3': unknown option '/x=3' after strategy 'donation' (donation takes "
      "/d=N)" },
    { "megakernel/shared/d2=3",
      "schedule 'megakernel/shared/d2=3': unknown option '/d2=3' after strategy 'shared' (shared takes no "
      "option)" },
    { "megakernel/stealing-donation/d=8/random",
      "schedule 'megakernel/stealing-donation/d=8/random': unexpected '/random' at the end" },
    { "megakernel/donation+local32/d=8", "schedule 'megakernel/donation+local32/d=8': unexpected '/d=8' at the end" },
    { "kernel-per-procedure/d=8",
      "schedule 'kernel-per-procedure/d=8': '/d=8' after kernel-per-procedure (a strategy is only valid with "
      "megakernel)" },
    { "bounded-batches/d=8",
      "schedule 'bounded-batches/d=8': unknown option '/d=8' (bounded-batches takes /p=N: at most N items "
      "per host iteration)" },
};

START_TEST(bad_labels_name_the_bad_part)
{
    for (size_t i = 0; i < COUNT(bad); ++i) {
        perma_schedule s;
        memset(&s, 0xab, sizeof s);
        perma_schedule untouched = s;
        perma_error error = { PERMA_OK, "" };
        ck_assert_int_eq(perma_schedule_parse(bad[i].label, &s, &error), PERMA_ERR_ARGUMENT);
        ck_assert_int_eq(error.status, PERMA_ERR_ARGUMENT);
        ck_assert_str_eq(error.message, bad[i].message);
        ck_assert_msg(memcmp(&s, &untouched, sizeof s) == 0, "'%s' changed *out", bad[i].label);
        /* Without an error struct only the status comes back. */
        ck_assert_int_eq(perma_schedule_parse(bad[i].label, &s, NULL), PERMA_ERR_ARGUMENT);
    }
}
END_TEST

START_TEST(null_label_is_an_argument_error)
{
    perma_schedule s;
    perma_error error = { PERMA_OK, "" };
    ck_assert_int_eq(perma_schedule_parse(NULL, &s, &error), PERMA_ERR_ARGUMENT);
    ck_assert_int_eq(error.status, PERMA_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, "schedule label is NULL");
}
END_TEST

START_TEST(long_label_message_is_truncated_not_overrun)
{
    char label[3 * PERMA_MESSAGE_MAX];
    memset(label, 'x', sizeof label - 1);
    label[sizeof label - 1] = '\0';
    perma_schedule s;
    perma_error error;
    ck_assert_int_eq(perma_schedule_parse(label, &s, &error), PERMA_ERR_ARGUMENT);
    ck_assert_uint_eq(strlen(error.message), PERMA_MESSAGE_MAX - 1);
    ck_assert(strncmp(error.message, "schedule 'xxx", 13) == 0);
}
END_TEST

START_TEST(format_leaves_out_fields_the_technique_ignores)
{
    perma_schedule s = { PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE, PERMA_STRATEGY_STEALING,
                         PERMA_VICTIM_ROUND_ROBIN, 32, 64, 16, 8 };
    expect_format(&s, "kernel-per-procedure");
    s.technique = PERMA_TECHNIQUE_BOUNDED_BATCHES;
    expect_format(&s, "bounded-batches/p=64");
    s.technique = PERMA_TECHNIQUE_MEGAKERNEL;
    expect_format(&s, "megakernel/stealing/round-robin+local32+wf8"); /* stealing does not donate */
    s.strategy = PERMA_STRATEGY_DONATION;
    expect_format(&s, "megakernel/donation/d=16+local32+wf8");
    s.strategy = PERMA_STRATEGY_STEALING_DONATION;
    expect_format(&s, "megakernel/stealing-donation/round-robin/d=16+local32+wf8");
    s.strategy = PERMA_STRATEGY_SHARED;
    expect_format(&s, "megakernel/shared+local32+wf8");
    s.local_queue_items = 0;
    expect_format(&s, "megakernel/shared+wf8");
}
END_TEST

START_TEST(format_rejects_unnamed_values_and_truncates)
{
    char buf[64] = "old";
    perma_schedule s = { (perma_technique)42, PERMA_STRATEGY_SHARED, PERMA_VICTIM_RANDOM, 0, 0, 0, 0 };
    ck_assert_int_eq(perma_schedule_format(&s, buf, sizeof buf), -1);
    ck_assert_str_eq(buf, "");
    s.technique = PERMA_TECHNIQUE_MEGAKERNEL;
    s.strategy = (perma_strategy)42;
    strcpy(buf, "old");
    ck_assert_int_eq(perma_schedule_format(&s, buf, sizeof buf), -1);
    ck_assert_str_eq(buf, "");
    s.strategy = PERMA_STRATEGY_STEALING;
    s.victim = (perma_victim)42;
    ck_assert_int_eq(perma_schedule_format(&s, buf, sizeof buf), -1);

    /* Like snprintf: the full length, the text cut to fit. */
    s.victim = PERMA_VICTIM_RANDOM;
    char small[12];
    ck_assert_int_eq(perma_schedule_format(&s, small, sizeof small), (int)strlen("megakernel/stealing/random"));
    ck_assert_str_eq(small, "megakernel/");
    ck_assert_int_eq(perma_schedule_format(&s, NULL, 0), (int)strlen("megakernel/stealing/random"));
}
END_TEST

/* Whether the schedule's strategy donates (its label takes /d=N). */
static bool donates(const perma_schedule *s)
{
    return s->technique == PERMA_TECHNIQUE_MEGAKERNEL &&
           (s->strategy == PERMA_STRATEGY_DONATION || s->strategy == PERMA_STRATEGY_STEALING_DONATION);
}

/* perma_schedule_all in order: what the tests, benchmarks and examples
 * iterate (and meson's test variants, runtime/schedules.py). */
static const char *const every_schedule[] = {
    "megakernel/shared",
    "megakernel/stealing/random",
    "megakernel/stealing/round-robin",
    "megakernel/donation",
    "megakernel/stealing-donation/random",
    "megakernel/stealing-donation/round-robin",
    "kernel-per-procedure",
    "bounded-batches",
};

static void expect_parse_error(const char *label, const char *message)
{
    perma_schedule s;
    perma_error error = { PERMA_OK, "" };
    ck_assert_msg(perma_schedule_parse(label, &s, &error) == PERMA_ERR_ARGUMENT, "'%s' parsed", label);
    ck_assert_int_eq(error.status, PERMA_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, message);
}

START_TEST(schedule_all_lists_every_schedule_in_order)
{
    perma_schedule s;
    unsigned n = 0;
    for (; perma_schedule_all(PERMA_SCHEDULES_ALL, n, &s) == PERMA_OK; ++n) {
        ck_assert_uint_lt(n, COUNT(every_schedule));
        expect_format(&s, every_schedule[n]);
        ck_assert_uint_eq(s.local_queue_items, 0);
        ck_assert_uint_eq(s.batch_limit, 0);
        ck_assert_uint_eq(s.donation_threshold, 0);
    }
    ck_assert_uint_eq(n, COUNT(every_schedule));
    /* Past the end *out stays as it was. */
    memset(&s, 0xab, sizeof s);
    perma_schedule untouched = s;
    ck_assert_int_eq(perma_schedule_all(PERMA_SCHEDULES_ALL, n, &s), PERMA_ERR_ARGUMENT);
    ck_assert_int_eq(perma_schedule_all(PERMA_SCHEDULES_ALL, ~0u, &s), PERMA_ERR_ARGUMENT);
    ck_assert(memcmp(&s, &untouched, sizeof s) == 0);
    ck_assert_int_eq(perma_schedule_all((perma_schedule_set)3, 0, &s), PERMA_ERR_ARGUMENT);
    ck_assert(memcmp(&s, &untouched, sizeof s) == 0);
}
END_TEST

/* The labels of a set, one after another with a space after each. */
static void set_labels(perma_schedule_set set, char *out, size_t size)
{
    perma_schedule s;
    out[0] = '\0';
    for (unsigned i = 0; perma_schedule_all(set, i, &s) == PERMA_OK; ++i) {
        char label[128];
        ck_assert_int_gt(perma_schedule_format(&s, label, sizeof label), 0);
        snprintf(out + strlen(out), size - strlen(out), "%s ", label);
    }
}

START_TEST(schedule_sets_leave_out_victims)
{
    char labels[1024];
    set_labels(PERMA_SCHEDULES_VICTIMS_ONCE, labels, sizeof labels);
    ck_assert_str_eq(labels, "megakernel/shared megakernel/stealing/random megakernel/stealing/round-robin "
                             "megakernel/donation megakernel/stealing-donation/random kernel-per-procedure "
                             "bounded-batches ");
    set_labels(PERMA_SCHEDULES_DEFAULT_VICTIM, labels, sizeof labels);
    ck_assert_str_eq(labels, "megakernel/shared megakernel/stealing/random megakernel/donation "
                             "megakernel/stealing-donation/random kernel-per-procedure bounded-batches ");
}
END_TEST

/* Every schedule of the table, with and without the options its technique
 * takes, formats to a label that parses back to it. */
START_TEST(every_schedule_round_trips)
{
    perma_schedule s;
    for (unsigned i = 0; perma_schedule_all(PERMA_SCHEDULES_ALL, i, &s) == PERMA_OK; ++i) {
        for (unsigned option = 0; option < 5; ++option) {
            perma_schedule variant = s;
            if ((option == 1 || option == 4) && s.technique == PERMA_TECHNIQUE_MEGAKERNEL)
                variant.local_queue_items = 32;
            if (option == 2 && s.technique == PERMA_TECHNIQUE_BOUNDED_BATCHES)
                variant.batch_limit = 64;
            if (option >= 3 && donates(&s))
                variant.donation_threshold = option == 3 ? 1 : 256;
            char label[128];
            int n = perma_schedule_format(&variant, label, sizeof label);
            ck_assert_int_gt(n, 0);
            ck_assert_uint_eq((size_t)n, strlen(label));
            perma_schedule back = parse_ok(label);
            ck_assert_msg(memcmp(&back, &variant, sizeof back) == 0, "'%s' parses to another schedule", label);
        }
    }
}
END_TEST

/* "a, b, c": every name from 0 on. */
static void join(const char *(*name_at)(int), char *out, size_t size)
{
    out[0] = '\0';
    for (int i = 0; name_at(i); ++i)
        snprintf(out + strlen(out), size - strlen(out), "%s%s", i ? ", " : "", name_at(i));
}

static const char *technique_at(int i) { return perma_technique_name((perma_technique)i); }
static const char *strategy_at(int i) { return perma_strategy_name((perma_strategy)i); }
static const char *victim_at(int i) { return perma_victim_name((perma_victim)i); }

/* Every name parses to its value, and every name appears in the list of
 * schedules; a misspelt name is refused with the whole list. */
START_TEST(every_name_parses_and_is_scheduled)
{
    char labels[1024];
    set_labels(PERMA_SCHEDULES_ALL, labels, sizeof labels);
    for (int i = 0; technique_at(i); ++i) {
        perma_technique t;
        ck_assert_int_eq(perma_technique_parse(technique_at(i), &t), PERMA_OK);
        ck_assert_int_eq(t, i);
        ck_assert_msg(strstr(labels, technique_at(i)), "no schedule of %s", technique_at(i));
    }
    for (int i = 0; strategy_at(i); ++i) {
        perma_strategy st;
        ck_assert_int_eq(perma_strategy_parse(strategy_at(i), &st), PERMA_OK);
        ck_assert_int_eq(st, i);
        char part[64];
        snprintf(part, sizeof part, "/%s", strategy_at(i));
        ck_assert_msg(strstr(labels, part), "no schedule of %s", strategy_at(i));
    }
    for (int i = 0; victim_at(i); ++i) {
        perma_victim v;
        ck_assert_int_eq(perma_victim_parse(victim_at(i), &v), PERMA_OK);
        ck_assert_int_eq(v, i);
        ck_assert_msg(strstr(labels, victim_at(i)), "no schedule of %s", victim_at(i));
    }
    char names[256], message[512];
    join(technique_at, names, sizeof names);
    snprintf(message, sizeof message, "schedule 'megakernal': unknown technique 'megakernal' (%s)", names);
    expect_parse_error("megakernal", message);
    join(strategy_at, names, sizeof names);
    snprintf(message, sizeof message, "schedule 'megakernel/sharde': unknown strategy 'sharde' (%s)", names);
    expect_parse_error("megakernel/sharde", message);
    join(victim_at, names, sizeof names);
    snprintf(message, sizeof message, "schedule 'megakernel/stealing/rr': unknown victim 'rr' (%s)", names);
    expect_parse_error("megakernel/stealing/rr", message);
}
END_TEST

/* What a schedule's technique or strategy does not take is refused, by
 * status and message, for every schedule of the table. */
START_TEST(every_schedule_refuses_what_it_does_not_take)
{
    perma_schedule s;
    for (unsigned i = 0; perma_schedule_all(PERMA_SCHEDULES_ALL, i, &s) == PERMA_OK; ++i) {
        char label[128], bad_label[160], message[512];
        perma_schedule_format(&s, label, sizeof label);
        const char *technique = perma_technique_name(s.technique), *strategy = perma_strategy_name(s.strategy);
        bool megakernel = s.technique == PERMA_TECHNIQUE_MEGAKERNEL;
        bool steals = s.strategy == PERMA_STRATEGY_STEALING || s.strategy == PERMA_STRATEGY_STEALING_DONATION;
        if (megakernel && !donates(&s)) {
            snprintf(bad_label, sizeof bad_label, "%s/d=4", label);
            snprintf(message, sizeof message, "schedule '%s': option '/d=4' after strategy '%s' (/d=N only "
                     "follows donation or stealing-donation)", bad_label, strategy);
            expect_parse_error(bad_label, message);
        }
        if (donates(&s)) {
            snprintf(bad_label, sizeof bad_label, "%s/d=4/d=4", label);
            snprintf(message, sizeof message, "schedule '%s': '/d=4' after another /d=N (give it once)",
                     bad_label);
            expect_parse_error(bad_label, message);
        }
        if (megakernel && !steals) {
            snprintf(bad_label, sizeof bad_label, "%s/random", label);
            snprintf(message, sizeof message, "schedule '%s': victim 'random' after strategy '%s' (a victim "
                     "only follows stealing or stealing-donation)", bad_label, strategy);
            expect_parse_error(bad_label, message);
        }
        if (megakernel && steals) {
            snprintf(bad_label, sizeof bad_label, "%s/random", label);
            snprintf(message, sizeof message, "schedule '%s': unexpected '/random' at the end", bad_label);
            expect_parse_error(bad_label, message);
        }
        if (!megakernel) {
            snprintf(bad_label, sizeof bad_label, "%s+local8", label);
            snprintf(message, sizeof message, "schedule '%s': '+local8' after %s (+localN and +wfN are only "
                     "valid with megakernel)", bad_label, technique);
            expect_parse_error(bad_label, message);
        }
        if (s.technique == PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE) {
            snprintf(bad_label, sizeof bad_label, "%s/shared", label);
            snprintf(message, sizeof message, "schedule '%s': '/shared' after %s (a strategy is only valid "
                     "with megakernel)", bad_label, technique);
            expect_parse_error(bad_label, message);
        }
        /* A misspelt last name: the list of the names that could go there. */
        snprintf(bad_label, sizeof bad_label, "%s!", label);
        const char *what = !megakernel ? "technique" : steals ? "victim" : "strategy";
        const char *(*name_at)(int) = !megakernel ? technique_at : steals ? victim_at : strategy_at;
        const char *last = strrchr(bad_label, '/') ? strrchr(bad_label, '/') + 1 : bad_label;
        snprintf(message, sizeof message, "schedule '%s': unknown %s '%s' (", bad_label, what, last);
        join(name_at, message + strlen(message), sizeof message - strlen(message));
        strcat(message, ")");
        expect_parse_error(bad_label, message);
    }
}
END_TEST

int main(void)
{
    Suite *suite = suite_create("schedule");
    TCase *tc = tcase_create("labels");
    tcase_add_test(tc, canonical_labels_round_trip);
    tcase_add_test(tc, short_forms_format_canonically);
    tcase_add_test(tc, parse_sets_every_field);
    tcase_add_test(tc, config_default_schedule_is_megakernel_shared);
    tcase_add_test(tc, bad_labels_name_the_bad_part);
    tcase_add_test(tc, null_label_is_an_argument_error);
    tcase_add_test(tc, long_label_message_is_truncated_not_overrun);
    tcase_add_test(tc, format_leaves_out_fields_the_technique_ignores);
    tcase_add_test(tc, format_rejects_unnamed_values_and_truncates);
    tcase_add_test(tc, schedule_all_lists_every_schedule_in_order);
    tcase_add_test(tc, schedule_sets_leave_out_victims);
    tcase_add_test(tc, every_schedule_round_trips);
    tcase_add_test(tc, every_name_parses_and_is_scheduled);
    tcase_add_test(tc, every_schedule_refuses_what_it_does_not_take);
    suite_add_tcase(suite, tc);
    return test_run_suite(suite) ? EXIT_FAILURE : EXIT_SUCCESS;
}
