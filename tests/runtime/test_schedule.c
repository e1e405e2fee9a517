/*
 * Schedule labels (perma_schedule_parse/format): every label the
 * benchmarks, examples and tests use parses and formats back, a default
 * perma_config's schedule is megakernel/shared, and bad labels are
 * PERMA_ERR_ARGUMENT with a message naming the bad part.  No device is
 * needed.
 */
#include "perma_test.h"

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

START_TEST(parse_sets_every_field)
{
    perma_schedule s = parse_ok("megakernel/stealing-donation/round-robin+local32");
    ck_assert_int_eq(s.technique, PERMA_TECHNIQUE_MEGAKERNEL);
    ck_assert_int_eq(s.strategy, PERMA_STRATEGY_STEALING_DONATION);
    ck_assert_int_eq(s.victim, PERMA_VICTIM_ROUND_ROBIN);
    ck_assert_uint_eq(s.local_queue_items, 32);
    ck_assert_uint_eq(s.batch_limit, 0);

    s = parse_ok("bounded-batches/p=64");
    ck_assert_int_eq(s.technique, PERMA_TECHNIQUE_BOUNDED_BATCHES);
    ck_assert_int_eq(s.strategy, PERMA_STRATEGY_SHARED);
    ck_assert_int_eq(s.victim, PERMA_VICTIM_RANDOM);
    ck_assert_uint_eq(s.local_queue_items, 0);
    ck_assert_uint_eq(s.batch_limit, 64);

    s = parse_ok("kernel-per-procedure");
    ck_assert_int_eq(s.technique, PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE);
    ck_assert_int_eq(s.strategy, PERMA_STRATEGY_SHARED);
    ck_assert_uint_eq(s.local_queue_items, 0);
    ck_assert_uint_eq(s.batch_limit, 0);

    s = parse_ok("megakernel/donation+local4096");
    ck_assert_uint_eq(s.local_queue_items, PERMA_MAX_LOCAL_QUEUE_ITEMS);
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
      "schedule 'kernel-per-procedure+local32': '+local32' after kernel-per-procedure (+localN is only "
      "valid with megakernel)" },
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
      "queue)" },
    { "megakernel/shared+local32/x", "schedule 'megakernel/shared+local32/x': unexpected '/x' at the end" },
    { "megakernel/stealing/random/x",
      "schedule 'megakernel/stealing/random/x': unexpected '/x' at the end" },
    { "megakernel/shared+local32+local64",
      "schedule 'megakernel/shared+local32+local64': unexpected '+local64' at the end" },
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
                         PERMA_VICTIM_ROUND_ROBIN, 32, 64 };
    expect_format(&s, "kernel-per-procedure");
    s.technique = PERMA_TECHNIQUE_BOUNDED_BATCHES;
    expect_format(&s, "bounded-batches/p=64");
    s.technique = PERMA_TECHNIQUE_MEGAKERNEL;
    expect_format(&s, "megakernel/stealing/round-robin+local32");
    s.strategy = PERMA_STRATEGY_DONATION;
    expect_format(&s, "megakernel/donation+local32");
}
END_TEST

START_TEST(format_rejects_unnamed_values_and_truncates)
{
    char buf[64] = "old";
    perma_schedule s = { (perma_technique)42, PERMA_STRATEGY_SHARED, PERMA_VICTIM_RANDOM, 0, 0 };
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
    suite_add_tcase(suite, tc);
    return test_run_suite(suite) ? EXIT_FAILURE : EXIT_SUCCESS;
}
