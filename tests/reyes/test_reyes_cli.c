/* reyes-render command line: parsing, and the exit codes of the program
 * (REYES_RENDER names the executable; those tests are skipped without it). */
#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "reyes_cli.h"

static int parse(reyes_cli *cli, char *message, int argc, char **argv)
{
    return reyes_cli_parse(argc, argv, cli, message, 512);
}

#define ARGS(...) ((char *[]){"reyes-render", __VA_ARGS__})
#define COUNT(...) ((int)(sizeof((char *[]){"reyes-render", __VA_ARGS__}) / sizeof(char *)))
#define PARSE(cli, message, ...) parse(cli, message, COUNT(__VA_ARGS__), ARGS(__VA_ARGS__))

START_TEST(test_defaults)
{
    reyes_cli cli;
    char message[512];
    char *argv[] = {"reyes-render"};
    ck_assert_int_eq(parse(&cli, message, 1, argv), PERMA_CLI_OK);
    ck_assert_uint_eq(cli.model_count, 0);
    ck_assert_str_eq(cli.output, "reyes.png");
    ck_assert_uint_eq(cli.render.width, 512);
    ck_assert_uint_eq(cli.render.grid, 16);
    ck_assert_float_eq(cli.render.shading_rate, 1.0f); /* the library's default is 0: fixed grids */
    ck_assert_uint_eq(cli.render.crack_fix, REYES_CRACK_FIX_POLYLINE); /* one pass at a rate */
    ck_assert_uint_eq(cli.render.occlusion_cull, 1);
    ck_assert_uint_eq(cli.render.bucket_width, 0);
    ck_assert(!cli.has_camera);
    ck_assert_int_eq(cli.render.area_stats, 0); /* no --stats: the areas are not tallied */
    reyes_cli_free(&cli);
    /* Fixed grids and displaced surfaces stitch unless told otherwise. */
    ck_assert_int_eq(PARSE(&cli, message, "--grid", "8"), PERMA_CLI_OK);
    ck_assert_float_eq(cli.render.shading_rate, 0.0f);
    ck_assert_uint_eq(cli.render.crack_fix, REYES_CRACK_FIX_STITCH);
    reyes_cli_free(&cli);
    ck_assert_int_eq(PARSE(&cli, message, "--displace", "bumps:0.1"), PERMA_CLI_OK);
    ck_assert_float_eq(cli.render.shading_rate, 1.0f);
    ck_assert_uint_eq(cli.render.crack_fix, REYES_CRACK_FIX_STITCH);
    reyes_cli_free(&cli);
    ck_assert_int_eq(PARSE(&cli, message, "--grid", "8", "--shading-rate", "2"), PERMA_CLI_OK);
    ck_assert_uint_eq(cli.render.crack_fix, REYES_CRACK_FIX_POLYLINE);
    reyes_cli_free(&cli);
    ck_assert_int_eq(PARSE(&cli, message, "--crack-fix", "none"), PERMA_CLI_OK);
    ck_assert_uint_eq(cli.render.crack_fix, REYES_CRACK_FIX_NONE);
    reyes_cli_free(&cli);
}
END_TEST

START_TEST(test_all_options)
{
    reyes_cli cli;
    char message[512];
    ck_assert_int_eq(PARSE(&cli, message, "a.bpt", "-o", "x.png", "--size", "320x200", "--bound=4",
                           "--grid", "8", "--spp", "9", "--max-depth", "12", "--camera",
                           "1,2,3,-4.5,0,1e1", "--fov", "30", "--technique", "megakernel",
                           "--strategy", "shared", "--stats", "s.json", "--groups", "2", "b.bpt",
                           "--backface", "--occlusion", "off", "--bucket", "32x16", "--crack-fix", "none", "--displace",
                           "png:dir/a:b.png:0.25", "--motion", "0.5,0,-1", "--motion-rotate", "0,1,2,-45", "--aperture", "0.1",
                           "--focus", "7", "--blur-algo", "bbox", "--blur-tile", "3",
                           "--blur-permutations", "64", "--time-samples", "8", "--",
                           "-c.bpt"),
                     PERMA_CLI_OK);
    ck_assert_uint_eq(cli.model_count, 3);
    ck_assert_str_eq(cli.models[0], "a.bpt");
    ck_assert_str_eq(cli.models[1], "b.bpt");
    ck_assert_str_eq(cli.models[2], "-c.bpt");
    ck_assert_str_eq(cli.output, "x.png");
    ck_assert_uint_eq(cli.render.width, 320);
    ck_assert_uint_eq(cli.render.height, 200);
    ck_assert_float_eq(cli.render.bound_px, 4.0f);
    ck_assert_uint_eq(cli.render.grid, 8);
    ck_assert_uint_eq(cli.render.spp, 9);
    ck_assert_uint_eq(cli.render.max_depth, 12);
    ck_assert(cli.has_camera);
    ck_assert_float_eq(cli.camera[3], -4.5f);
    ck_assert_float_eq(cli.camera[5], 10.0f);
    ck_assert_float_eq(cli.fov_deg, 30.0f);
    ck_assert_str_eq(cli.stats_path, "s.json");
    ck_assert_int_eq(cli.render.area_stats, 1); /* the JSON's micropolygon_area */
    ck_assert_uint_eq(cli.render.work_groups, 2);
    ck_assert_int_eq(cli.render.backface_cull, 1);
    ck_assert_uint_eq(cli.render.occlusion_cull, 0);
    ck_assert_uint_eq(cli.render.bucket_width, 32);
    ck_assert_uint_eq(cli.render.bucket_height, 16);
    ck_assert_uint_eq(cli.render.crack_fix, REYES_CRACK_FIX_NONE);
    ck_assert_uint_eq(cli.render.displace_mode, REYES_DISPLACE_MAP);
    ck_assert_str_eq(cli.render.displace_map, "dir/a:b.png");
    ck_assert_float_eq(cli.render.displace_amplitude, 0.25f);
    ck_assert_float_eq(cli.render.motion[0], 0.5f);
    ck_assert_float_eq(cli.render.motion[2], -1.0f);
    ck_assert_float_eq(cli.render.motion_axis[0], 0.0f);
    ck_assert_float_eq(cli.render.motion_axis[2], 2.0f);
    ck_assert_float_eq(cli.render.motion_angle_deg, -45.0f);
    ck_assert_float_eq(cli.render.aperture, 0.1f);
    ck_assert_float_eq(cli.render.focus, 7.0f);
    ck_assert_uint_eq(cli.render.time_samples, 8);
    ck_assert_uint_eq(cli.render.blur_algo, REYES_BLUR_BBOX);
    ck_assert_uint_eq(cli.render.blur_tile, 3);
    ck_assert_uint_eq(cli.render.blur_permutations, 64);
    reyes_cli_free(&cli);
}
END_TEST

/* The scale-out options: a device list (checked when used), frames and
 * an orbit; without them one image on one device. */
START_TEST(test_scale_out_options)
{
    reyes_cli cli;
    char message[512];
    ck_assert_int_eq(PARSE(&cli, message, "--devices", "0:0/2,1:0", "--frames", "24", "--orbit", "-90",
                           "--rank-timeout", "30", "--coordinator-only"),
                     PERMA_CLI_OK);
    ck_assert_float_eq(cli.rank_timeout, 30.0f);
    ck_assert(cli.coordinator_only);
    ck_assert_str_eq(cli.devices, "0:0/2,1:0");
    ck_assert_uint_eq(cli.frames, 24);
    ck_assert_float_eq(cli.orbit_deg, -90.0f);
    ck_assert(cli.orbit_given);
    reyes_cli_free(&cli);
    ck_assert_int_eq(PARSE(&cli, message, "-o", "x.png"), PERMA_CLI_OK);
    ck_assert_ptr_null(cli.devices);
    ck_assert_uint_eq(cli.frames, 0);
    ck_assert(!cli.orbit_given);
    ck_assert(!cli.coordinator_only);
    ck_assert_float_eq(cli.rank_timeout, 0.0f);
    reyes_cli_free(&cli);
}
END_TEST

/* Each blur algorithm name lands in the options; the defaults are
 * interleaved with 4 x 4 tiles and 8 permutations. */
START_TEST(test_blur_algorithms)
{
    const char *names[] = {"simple", "interleaved", "bbox"};
    const unsigned values[] = {REYES_BLUR_SIMPLE, REYES_BLUR_INTERLEAVED, REYES_BLUR_BBOX};
    reyes_cli cli;
    char message[512];
    ck_assert_int_eq(PARSE(&cli, message, "--motion", "1,0,0"), PERMA_CLI_OK);
    ck_assert_uint_eq(cli.render.blur_algo, REYES_BLUR_INTERLEAVED);
    ck_assert_uint_eq(cli.render.blur_tile, 4);
    ck_assert_uint_eq(cli.render.blur_permutations, 8);
    reyes_cli_free(&cli);
    for (int k = 0; k < 3; ++k) {
        ck_assert_int_eq(PARSE(&cli, message, "--blur-algo", (char *)names[k], "--blur-tile=1",
                               "--blur-permutations", "1"),
                         PERMA_CLI_OK);
        ck_assert_uint_eq(cli.render.blur_algo, values[k]);
        ck_assert_str_eq(reyes_blur_algo_name(cli.render.blur_algo), names[k]);
        ck_assert_uint_eq(cli.render.blur_tile, 1);
        ck_assert_uint_eq(cli.render.blur_permutations, 1);
        reyes_cli_free(&cli);
    }
}
END_TEST

/* Every technique, strategy and victim name of the runtime is accepted and
 * lands in the render options passed to perma_config. */
START_TEST(test_scheduling_names)
{
    for (perma_technique t = 0; perma_technique_name(t); ++t) {
        for (perma_strategy s = 0; perma_strategy_name(s); ++s) {
            const char *technique = perma_technique_name(t), *strategy = perma_strategy_name(s);
            reyes_cli cli;
            char message[512];
            ck_assert_int_eq(PARSE(&cli, message, "--technique", (char *)technique, "--strategy",
                                   (char *)strategy, "--victim", "round-robin", "--local-queue",
                                   "128", "--batch-limit", "512"),
                             PERMA_CLI_OK);
            ck_assert_int_eq(cli.render.schedule.technique, t);
            ck_assert_int_eq(cli.render.schedule.strategy, s);
            ck_assert_int_eq(cli.render.schedule.victim, PERMA_VICTIM_ROUND_ROBIN);
            ck_assert_uint_eq(cli.render.schedule.local_queue_items, 128);
            ck_assert_uint_eq(cli.render.schedule.batch_limit, 512);
            reyes_cli_free(&cli);
        }
    }
}
END_TEST

/* --schedule sets every scheduling field from one label; a later option
 * overrides one of them. */
START_TEST(test_schedule_label)
{
    reyes_cli cli;
    char message[512];
    ck_assert_int_eq(PARSE(&cli, message, "--batch-limit", "512", "--schedule",
                           "megakernel/stealing/round-robin+local32"),
                     PERMA_CLI_OK);
    ck_assert_int_eq(cli.render.schedule.technique, PERMA_TECHNIQUE_MEGAKERNEL);
    ck_assert_int_eq(cli.render.schedule.strategy, PERMA_STRATEGY_STEALING);
    ck_assert_int_eq(cli.render.schedule.victim, PERMA_VICTIM_ROUND_ROBIN);
    ck_assert_uint_eq(cli.render.schedule.local_queue_items, 32);
    ck_assert_uint_eq(cli.render.schedule.batch_limit, 0);
    reyes_cli_free(&cli);
    ck_assert_int_eq(PARSE(&cli, message, "--schedule", "bounded-batches/p=64", "--local-queue", "8"),
                     PERMA_CLI_OK);
    ck_assert_int_eq(cli.render.schedule.technique, PERMA_TECHNIQUE_BOUNDED_BATCHES);
    ck_assert_int_eq(cli.render.schedule.strategy, PERMA_STRATEGY_SHARED);
    ck_assert_uint_eq(cli.render.schedule.batch_limit, 64);
    ck_assert_uint_eq(cli.render.schedule.local_queue_items, 8);
    reyes_cli_free(&cli);
}
END_TEST

/* The subdivision criterion and its parameters; flatness options without
 * it, and wedges without it, are refused with a message naming them. */
START_TEST(test_subdivision_options)
{
    reyes_cli cli;
    char message[512];
    ck_assert_int_eq(PARSE(&cli, message, "--subdivision", "tiered", "--epsilon", "0.25",
                           "--lambda", "1"),
                     PERMA_CLI_OK);
    ck_assert_uint_eq(cli.render.subdivision, REYES_SUBDIVISION_TIERED);
    ck_assert_float_eq(cli.render.flat_epsilon, 0.25f);
    ck_assert_float_eq(cli.render.flat_lambda, 1.0f);
    reyes_cli_free(&cli);
    ck_assert_float_eq(cli.render.flat_bound_px, 0.0f); /* grid - 1 */
    reyes_cli_free(&cli);
    ck_assert_int_eq(PARSE(&cli, message, "--subdivision", "bound", "--bound", "4"), PERMA_CLI_OK);
    ck_assert_uint_eq(cli.render.subdivision, REYES_SUBDIVISION_BOUND);
    ck_assert_float_eq(cli.render.flat_bound_px, 0.0f);
    reyes_cli_free(&cli);
    /* With tiered, --bound (before or after) is its largest sub-patch. */
    ck_assert_int_eq(PARSE(&cli, message, "--bound", "24", "--subdivision", "tiered", "--crack-fix",
                           "wedge"),
                     PERMA_CLI_OK);
    ck_assert_float_eq(cli.render.flat_bound_px, 24.0f);
    ck_assert_uint_eq(cli.render.crack_fix, REYES_CRACK_FIX_WEDGE);
    reyes_cli_free(&cli);

    struct { int argc; char **argv; const char *needle; } cases[] = {
        { COUNT("--subdivision", "flat"), ARGS("--subdivision", "flat"),
          "--subdivision 'flat': expected bound or tiered" },
        { COUNT("--subdivision", "tiered", "--epsilon", "0"),
          ARGS("--subdivision", "tiered", "--epsilon", "0"), "--epsilon '0': expected a number in 0.01..1000" },
        { COUNT("--subdivision", "tiered", "--epsilon", "1e9"),
          ARGS("--subdivision", "tiered", "--epsilon", "1e9"), "--epsilon '1e9'" },
        { COUNT("--subdivision", "tiered", "--lambda", "1.5"),
          ARGS("--subdivision", "tiered", "--lambda", "1.5"), "--lambda '1.5': expected a number in 0..1" },
        { COUNT("--subdivision", "tiered", "--lambda", "-0.1"),
          ARGS("--subdivision", "tiered", "--lambda", "-0.1"), "--lambda '-0.1'" },
        { COUNT("--crack-fix", "wedge"), ARGS("--crack-fix", "wedge"),
          "--crack-fix wedge needs --subdivision tiered" },
        { COUNT("--epsilon", "1"), ARGS("--epsilon", "1"),
          "--epsilon and --lambda apply to --subdivision tiered" },
        { COUNT("--subdivision", "bound", "--lambda", "0"),
          ARGS("--subdivision", "bound", "--lambda", "0"), "apply to --subdivision tiered" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        ck_assert_int_eq(parse(&cli, message, cases[i].argc, cases[i].argv), PERMA_CLI_USAGE);
        ck_assert_msg(strstr(message, cases[i].needle) != NULL, "case %zu: '%s' lacks '%s'", i,
                      message, cases[i].needle);
        reyes_cli_free(&cli);
    }
}
END_TEST

/* Dicing: a shading rate of 1 by default; --grid alone is fixed N x N
 * dicing (today's images); both: the rate with at most N per side;
 * wedges and the C reference dice fixed grids and refuse a rate. */
START_TEST(test_dicing_options)
{
    reyes_cli cli;
    char message[512];
    ck_assert_int_eq(PARSE(&cli, message, "--grid", "8"), PERMA_CLI_OK);
    ck_assert_uint_eq(cli.render.grid, 8);
    ck_assert_float_eq(cli.render.shading_rate, 0.0f);
    reyes_cli_free(&cli);
    ck_assert_int_eq(PARSE(&cli, message, "--shading-rate", "0.25", "--grid", "32"), PERMA_CLI_OK);
    ck_assert_float_eq(cli.render.shading_rate, 0.25f);
    ck_assert_uint_eq(cli.render.grid, 32);
    reyes_cli_free(&cli);
    ck_assert_int_eq(PARSE(&cli, message, "--subdivision", "tiered", "--crack-fix", "wedge"), PERMA_CLI_OK);
    ck_assert_float_eq(cli.render.shading_rate, 0.0f);
    reyes_cli_free(&cli);
    ck_assert_int_eq(PARSE(&cli, message, "--reference"), PERMA_CLI_OK);
    ck_assert_float_eq(cli.render.shading_rate, 0.0f);
    reyes_cli_free(&cli);
    struct { int argc; char **argv; const char *needle; } cases[] = {
        { COUNT("--shading-rate", "0"), ARGS("--shading-rate", "0"),
          "--shading-rate '0': expected a number in 0.01..10000" },
        { COUNT("--shading-rate", "x"), ARGS("--shading-rate", "x"), "--shading-rate 'x'" },
        { COUNT("--shading-rate", "2", "--subdivision", "tiered", "--crack-fix", "wedge"),
          ARGS("--shading-rate", "2", "--subdivision", "tiered", "--crack-fix", "wedge"),
          "--shading-rate cannot be combined with --crack-fix wedge (fixed grids only)" },
        { COUNT("--reference", "--shading-rate", "2"), ARGS("--reference", "--shading-rate", "2"),
          "--shading-rate cannot be combined with --reference" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        ck_assert_int_eq(parse(&cli, message, cases[i].argc, cases[i].argv), PERMA_CLI_USAGE);
        ck_assert_msg(strstr(message, cases[i].needle) != NULL, "case %zu: '%s' lacks '%s'", i, message,
                      cases[i].needle);
        reyes_cli_free(&cli);
    }
}
END_TEST

/* Each bad command line gives PERMA_CLI_USAGE and a message with `needle`. */
START_TEST(test_bad_usage)
{
    struct { int argc; char **argv; const char *needle; } cases[] = {
        { COUNT("--technique", "warp"), ARGS("--technique", "warp"),
          "--technique 'warp': expected megakernel, kernel-per-procedure or bounded-batches" },
        { COUNT("--strategy", "steal"), ARGS("--strategy", "steal"),
          "--strategy 'steal': expected shared, stealing, donation or stealing-donation" },
        { COUNT("--victim", "any"), ARGS("--victim", "any"), "--victim 'any': expected random or round-robin" },
        { COUNT("--schedule", "megakernel/stealng"), ARGS("--schedule", "megakernel/stealng"),
          "--schedule 'megakernel/stealng': unknown strategy 'stealng' (shared, stealing, "
          "donation, stealing-donation)" },
        { COUNT("--schedule", "kernel-per-procedure/shared"),
          ARGS("--schedule", "kernel-per-procedure/shared"), "a strategy is only valid with megakernel" },
        { COUNT("--local-queue", "-3"), ARGS("--local-queue", "-3"), "--local-queue" },
        /* The runtime's range (PERMA_MAX_LOCAL_QUEUE_ITEMS), named as the option. */
        { COUNT("--local-queue", "65536"), ARGS("--local-queue", "65536"),
          "--local-queue '65536': expected a whole number in 0..4096" },
        { COUNT("--local-queue", "4097"), ARGS("--local-queue", "4097"), "--local-queue '4097'" },
        { COUNT("--schedule", "megakernel/shared+local65536"), ARGS("--schedule", "megakernel/shared+local65536"),
          "'+local65536': at most 4096 items in a local queue" },
        { COUNT("--batch-limit", "0"), ARGS("--batch-limit", "0"), "--batch-limit" },
        { COUNT("--size", "100"), ARGS("--size", "100"), "WxH" },
        { COUNT("--size", "0x10"), ARGS("--size", "0x10"), "--size" },
        { COUNT("--bucket", "0x8"), ARGS("--bucket", "0x8"), "--bucket" },
        { COUNT("--bucket", "64"), ARGS("--bucket", "64"), "--bucket '64': expected WxH" },
        { COUNT("--crack-fix", "glue"), ARGS("--crack-fix", "glue"),
          "--crack-fix 'glue': expected none, stitch, wedge or polyline" },
        { COUNT("--displace", "bumps"), ARGS("--displace", "bumps"), "bumps:AMPLITUDE" },
        { COUNT("--displace", "bumps:x"), ARGS("--displace", "bumps:x"), "--displace 'bumps:x': amplitude 'x' is not a number" },
        { COUNT("--displace", "png:0.1"), ARGS("--displace", "png:0.1"), "png:FILE:AMPLITUDE" },
        { COUNT("--displace", "waves:1"), ARGS("--displace", "waves:1"), "--displace 'waves:1'" },
        { COUNT("--motion", "1,2"), ARGS("--motion", "1,2"), "3 numbers" },
        { COUNT("--motion-rotate", "0,0,1"), ARGS("--motion-rotate", "0,0,1"),
          "--motion-rotate '0,0,1': expected 4 numbers ax,ay,az,DEG" },
        { COUNT("--motion-rotate", "0,0,1,x"), ARGS("--motion-rotate", "0,0,1,x"),
          "--motion-rotate '0,0,1,x': 'x' is not a number" },
        { COUNT("--motion-rotate", "0,0,0,30"), ARGS("--motion-rotate", "0,0,0,30"),
          "--motion-rotate '0,0,0,30': the axis must be finite and not zero" },
        { COUNT("--motion-rotate", "0,0,1,361"), ARGS("--motion-rotate", "0,0,1,361"),
          "--motion-rotate '0,0,1,361': the angle must be in -360..360 degrees" },
        { COUNT("--motion-rotate", "0,0,1,inf"), ARGS("--motion-rotate", "0,0,1,inf"),
          "--motion-rotate '0,0,1,inf': 'inf' is not a number" },
        { COUNT("--aperture", "-1"), ARGS("--aperture", "-1"), "--aperture" },
        { COUNT("--focus", "0"), ARGS("--focus", "0"), "--focus" },
        { COUNT("--blur-algo", "fancy"), ARGS("--blur-algo", "fancy"),
          "--blur-algo 'fancy': expected simple, interleaved or bbox" },
        { COUNT("--blur-algo", ""), ARGS("--blur-algo", ""), "--blur-algo '': expected simple" },
        { COUNT("--blur-tile", "0"), ARGS("--blur-tile", "0"), "--blur-tile '0': expected" },
        { COUNT("--blur-tile", "9"), ARGS("--blur-tile", "9"), "--blur-tile '9'" },
        { COUNT("--blur-tile", "2x"), ARGS("--blur-tile", "2x"), "--blur-tile '2x'" },
        { COUNT("--blur-tile"), ARGS("--blur-tile"), "--blur-tile needs a value K" },
        { COUNT("--blur-permutations", "0"), ARGS("--blur-permutations", "0"),
          "--blur-permutations '0': expected a whole number in 1..64" },
        { COUNT("--blur-permutations", "65"), ARGS("--blur-permutations", "65"),
          "--blur-permutations '65'" },
        { COUNT("--blur-permutations", "-1"), ARGS("--blur-permutations", "-1"),
          "--blur-permutations '-1'" },
        { COUNT("--time-samples", "0"), ARGS("--time-samples", "0"), "--time-samples" },
        { COUNT("--grid", "1"), ARGS("--grid", "1"), "--grid" },
        { COUNT("--grid", "99"), ARGS("--grid", "99"), "--grid" },
        { COUNT("--spp", "-1"), ARGS("--spp", "-1"), "--spp" },
        { COUNT("--bound", "nan"), ARGS("--bound", "nan"), "--bound" },
        { COUNT("--camera", "1,2,3"), ARGS("--camera", "1,2,3"), "6 numbers" },
        { COUNT("--camera", "1,2,3,4,5,6,7"), ARGS("--camera", "1,2,3,4,5,6,7"), "6 numbers" },
        { COUNT("--camera", "1,2,x,4,5,6"), ARGS("--camera", "1,2,x,4,5,6"), "'x'" },
        { COUNT("--fov", "180"), ARGS("--fov", "180"), "--fov" },
        { COUNT("--groups", "0"), ARGS("--groups", "0"), "--groups" },
        { COUNT("--max-depth", " -0"), ARGS("--max-depth", " -0"), "--max-depth" },
        { COUNT("--groups", " +5"), ARGS("--groups", " +5"), "--groups" },
        { COUNT("--frames", "0"), ARGS("--frames", "0"), "--frames '0': expected a whole number in 1..100000" },
        { COUNT("--frames", "100001"), ARGS("--frames", "100001"), "--frames '100001'" },
        { COUNT("--orbit", "x", "--frames", "2"), ARGS("--orbit", "x", "--frames", "2"),
          "--orbit 'x': expected a number in -36000..36000" },
        { COUNT("--orbit", "90"), ARGS("--orbit", "90"), "--orbit needs --frames" },
        { COUNT("--devices", ""), ARGS("--devices", ""), "--devices '': expected a device list" },
        { COUNT("--rank-timeout", "0.5"), ARGS("--rank-timeout", "0.5"),
          "--rank-timeout '0.5': expected a number in 1..1e6" },
        { COUNT("--frobnicate"), ARGS("--frobnicate"), "unknown option '--frobnicate'" },
        { COUNT("-o"), ARGS("-o"), "needs a value" },
        { COUNT("--help=yes"), ARGS("--help=yes"), "--help takes no value" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        reyes_cli cli;
        char message[512];
        ck_assert_int_eq(parse(&cli, message, cases[i].argc, cases[i].argv), PERMA_CLI_USAGE);
        ck_assert_msg(strstr(message, cases[i].needle) != NULL, "case %zu: '%s' lacks '%s'", i,
                      message, cases[i].needle);
        reyes_cli_free(&cli);
    }
}
END_TEST

/* Run the program with its output streams redirected so (e.g. "2>&1");
 * returns its exit status and the start of what it wrote to the pipe. */
static int run_redirected(const char *arguments, const char *redirect, char *output, size_t size)
{
    const char *program = getenv("REYES_RENDER");
    char command[1024];
    snprintf(command, sizeof command, "'%s' %s %s", program, arguments, redirect);
    FILE *p = popen(command, "r");
    ck_assert_ptr_nonnull(p);
    size_t n = fread(output, 1, size - 1, p);
    output[n] = '\0';
    char rest[256];
    while (fread(rest, 1, sizeof rest, p) > 0) {
        /* drain, so the program never blocks on a full pipe */
    }
    int status = pclose(p);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* Its exit status and the start of its output (both streams). */
static int run_program(const char *arguments, char *output, size_t size)
{
    return run_redirected(arguments, "2>&1", output, size);
}

START_TEST(test_program_exit_codes)
{
    if (!getenv("REYES_RENDER"))
        return;
    char output[8192];
    ck_assert_int_eq(run_program("--technique nope", output, sizeof output), 2);
    ck_assert_msg(strstr(output, "--technique 'nope': expected megakernel, kernel-per-procedure or "
                                 "bounded-batches (see --help)") != NULL, "%s", output);
    ck_assert_int_eq(run_program("--strategy nope", output, sizeof output), 2);
    ck_assert_msg(strstr(output, "expected shared, stealing, donation or stealing-donation") != NULL, "%s",
                  output);
    /* Refused by the option's range, before the runtime would refuse it. */
    ck_assert_int_eq(run_program("--local-queue 65536 -o /tmp/unused.png", output, sizeof output), 2);
    ck_assert_msg(strstr(output, "--local-queue '65536': expected a whole number in 0..4096") != NULL, "%s", output);
    ck_assert_int_eq(run_program("--bogus", output, sizeof output), 2);
    ck_assert_msg(strstr(output, "--bogus") != NULL, "%s", output);
    ck_assert_int_eq(run_program("--blur-algo fancy", output, sizeof output), 2);
    ck_assert_msg(strstr(output, "expected simple, interleaved or bbox") != NULL, "%s", output);
    ck_assert_int_eq(run_program("--blur-tile 99", output, sizeof output), 2);
    ck_assert_msg(strstr(output, "--blur-tile") != NULL, "%s", output);
    ck_assert_int_eq(run_program("--blur-permutations 0", output, sizeof output), 2);
    ck_assert_msg(strstr(output, "--blur-permutations") != NULL, "%s", output);
    ck_assert_int_eq(run_program("--help", output, sizeof output), 0);
    ck_assert_msg(strstr(output, "--max-depth") != NULL, "%s", output);
    ck_assert_msg(strstr(output, "--blur-algo NAME") != NULL && strstr(output, "--blur-tile K") != NULL
                  && strstr(output, "--blur-permutations P") != NULL, "%s", output);
    /* A malformed device list is bad usage, a missing device a failure. */
    ck_assert_int_eq(run_program("--devices 0:x -o /tmp/unused.png", output, sizeof output), 2);
    ck_assert_msg(strstr(output, "entry '0:x' is not of the form") != NULL, "%s", output);
    ck_assert_int_eq(run_program("--devices 0:0,9:0 -o /tmp/unused.png", output, sizeof output), 1);
    ck_assert_msg(strstr(output, "--devices: device list '0:0,9:0': OpenCL platform 9 requested") != NULL,
                  "%s", output);
    ck_assert_int_eq(run_program("--version", output, sizeof output), 0);
    ck_assert_msg(strstr(output, "reyes-render") != NULL, "%s", output);
    /* A file error is a failure (1), not a usage error, and names the file. */
    ck_assert_int_eq(run_program("/nonexistent/model.bpt -o /tmp/unused.png", output, sizeof output), 1);
    ck_assert_msg(strstr(output, "/nonexistent/model.bpt") != NULL, "%s", output);
}
END_TEST

/* Every line of `text` is a progress line of the program for `unit`
 * ("PROGRAM: D/T UNIT, P%, E elapsed[, about L left]"), the items done
 * never go back, and the last line is the whole job, 100%.  Returns the
 * lines. */
static unsigned expect_progress_lines(const char *text, const char *unit, unsigned total)
{
    unsigned lines = 0, last_done = 0;
    double last_percent = -1.0;
    for (const char *line = text; *line;) {
        const char *end = strchr(line, '\n');
        ck_assert_msg(end != NULL, "a progress line without its newline: '%s'", line);
        char copy[512];
        size_t length = (size_t)(end - line);
        ck_assert_uint_lt(length, sizeof copy);
        memcpy(copy, line, length);
        copy[length] = '\0';
        const char *colon = strstr(copy, ": ");
        ck_assert_msg(colon != NULL, "not a progress line: '%s'", copy);
        unsigned done = 0, all = 0;
        double percent = 0, elapsed = 0;
        char seen_unit[32], rest[128] = "";
        int fields = sscanf(colon + 2, "%u/%u %31[a-z], %lf%%, %lf s elapsed%127[^\n]", &done, &all, seen_unit,
                            &percent, &elapsed, rest);
        ck_assert_msg(fields >= 5, "not a progress line: '%s'", copy);
        ck_assert_str_eq(seen_unit, unit);
        ck_assert_uint_eq(all, total);
        ck_assert_uint_ge(done, last_done);
        ck_assert_msg(percent >= 0.0 && percent <= 100.0, "'%s'", copy);
        ck_assert_msg(!rest[0] || strncmp(rest, ", about ", 8) == 0, "after the time: '%s'", rest);
        last_done = done;
        last_percent = percent;
        ++lines;
        line = end + 1;
    }
    ck_assert_uint_eq(last_done, total);
    ck_assert_msg(last_percent == 100.0, "the last line says %.1f%%", last_percent);
    return lines;
}

START_TEST(test_program_progress)
{
    if (!getenv("REYES_RENDER"))
        return;
    char output[16384];
    /* --progress into a pipe: a line at the start and one at the end (at
     * least), stdout's summary elsewhere. */
    ck_assert_int_eq(run_redirected("--size 64x64 --bucket 32x32 --progress -o /tmp/reyes-progress.png",
                                    "2>&1 >/dev/null", output, sizeof output), 0);
    ck_assert_uint_ge(expect_progress_lines(output, "buckets", 4), 2);
    ck_assert_msg(strstr(output, ": 0/4 buckets, 0.0%, ") != NULL, "no line at the start: %s", output);
    /* Frames (the farm's pool). */
    ck_assert_int_eq(run_redirected("--size 32x24 --frames 2 --progress -o /tmp/reyes-progress.png",
                                    "2>&1 >/dev/null", output, sizeof output), 0);
    ck_assert_uint_ge(expect_progress_lines(output, "frames", 2), 2);
    /* Not a terminal and no --progress: no line. */
    ck_assert_int_eq(run_redirected("--size 64x64 --bucket 32x32 -o /tmp/reyes-progress.png", "2>&1 >/dev/null",
                                    output, sizeof output), 0);
    ck_assert_str_eq(output, "");
    ck_assert_int_eq(run_program("--progress --quiet", output, sizeof output), 2);
    ck_assert_msg(strstr(output, "--progress and --quiet contradict each other") != NULL, "%s", output);
    remove("/tmp/reyes-progress.png");
    remove("/tmp/reyes-progress-0001.png");
    remove("/tmp/reyes-progress-0002.png");
}
END_TEST

/* --quiet: nothing at all on success (the image is written), the error on
 * failure. */
START_TEST(test_program_quiet)
{
    if (!getenv("REYES_RENDER"))
        return;
    char output[8192];
    remove("/tmp/reyes-quiet.png");
    ck_assert_int_eq(run_program("--size 64x64 --bucket 32x32 --quiet -o /tmp/reyes-quiet.png", output,
                                 sizeof output), 0);
    ck_assert_msg(output[0] == '\0', "--quiet printed: %s", output);
    FILE *png = fopen("/tmp/reyes-quiet.png", "rb");
    ck_assert_ptr_nonnull(png);
    fclose(png);
    ck_assert_int_eq(run_program("--size 32x24 --frames 2 -q -o /tmp/reyes-quiet.png", output, sizeof output), 0);
    ck_assert_msg(output[0] == '\0', "--quiet printed: %s", output);
    ck_assert_int_eq(run_program("--quiet /nonexistent/model.bpt -o /tmp/reyes-quiet.png", output, sizeof output),
                     1);
    ck_assert_msg(strstr(output, "/nonexistent/model.bpt") != NULL, "%s", output);
    remove("/tmp/reyes-quiet.png");
    remove("/tmp/reyes-quiet-0001.png");
    remove("/tmp/reyes-quiet-0002.png");
}
END_TEST

static Suite *cli_suite(void)
{
    Suite *s = suite_create("reyes_cli");
    TCase *tc = tcase_create("cli");
    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, test_defaults);
    tcase_add_test(tc, test_dicing_options);
    tcase_add_test(tc, test_all_options);
    tcase_add_test(tc, test_scheduling_names);
    tcase_add_test(tc, test_schedule_label);
    tcase_add_test(tc, test_subdivision_options);
    tcase_add_test(tc, test_blur_algorithms);
    tcase_add_test(tc, test_bad_usage);
    tcase_add_test(tc, test_scale_out_options);
    tcase_add_test(tc, test_program_exit_codes);
    suite_add_tcase(s, tc);
    /* Renders: the first compiles the Reyes megakernel unless PoCL has it. */
    TCase *renders = tcase_create("renders");
    tcase_set_timeout(renders, 300);
    tcase_add_test(renders, test_program_progress);
    tcase_add_test(renders, test_program_quiet);
    suite_add_tcase(s, renders);
    return s;
}

int main(void)
{
    SRunner *runner = srunner_create(cli_suite());
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
