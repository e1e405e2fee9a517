/*
 * The options of reyes-render: every option is one row of `cli_options[]`
 * (name, argument, handler, help); an option whose value is one of a list
 * of names, or a flag, has no handler but a field (where the value goes,
 * and the names).  Technique, strategy and victim names are the runtime's
 * (perma_*_name), so new ones work here without a change.  The argument
 * walk is reyes_cli.c, the --help text reyes_cli_usage.c.
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "reyes_cli_internal.h"

#define COUNT_OF(a) (sizeof(a) / sizeof((a)[0]))
#define REYES_MAX_FRAMES 100000u

/* The name of enum value `value`, or NULL past the last one. */
typedef const char *(*name_of)(int value);

static const char *name_in(const char *const *names, size_t count, int value)
{
    return value >= 0 && (size_t)value < count ? names[value] : NULL;
}

static const char *crack_fix_name(int value)
{
    static const char *const names[] = { "none", "stitch", "wedge" }; /* REYES_CRACK_FIX_* */
    return name_in(names, COUNT_OF(names), value);
}

static const char *subdivision_name(int value)
{
    static const char *const names[] = { "bound", "tiered" }; /* REYES_SUBDIVISION_* */
    return name_in(names, COUNT_OF(names), value);
}

static const char *blur_algo_name(int value)
{
    return value < 0 ? NULL : reyes_blur_algo_name((unsigned)value);
}

static const char *technique_name(int value)
{
    return perma_technique_name((perma_technique)value);
}

static const char *strategy_name(int value)
{
    return perma_strategy_name((perma_strategy)value);
}

static const char *victim_name(int value)
{
    return perma_victim_name((perma_victim)value);
}

/* What an option without a handler does to reyes_cli: a flag sets its int
 * field to 1; an option whose value is one of a list of names stores the
 * name's index in its unsigned or enum field. */
typedef struct cli_field {
    size_t offset;
    const char *kind; /* a list: what the message calls its names */
    name_of names;    /* a list: the names, value 0 on; NULL for a flag */
} cli_field;

#define FLAG(field) (&(const cli_field){ offsetof(reyes_cli, field), NULL, NULL })
#define CHOICE(kind, names, field) (&(const cli_field){ offsetof(reyes_cli, field), kind, names })

/* The fields CHOICE writes are all unsigned-sized. */
_Static_assert(sizeof(perma_technique) == sizeof(unsigned) && sizeof(perma_strategy) == sizeof(unsigned) &&
               sizeof(perma_victim) == sizeof(unsigned), "enum fields are written as unsigned");

/* Set the field, or say "unknown KIND 'NAME'; valid: a b c". */
static int set_field(reyes_cli *cli, const cli_field *field, const char *name, char *message, size_t size)
{
    char *at = (char *)cli + field->offset;
    if (!field->names) {
        int on = 1;
        memcpy(at, &on, sizeof on);
        return REYES_CLI_OK;
    }
    for (int v = 0; field->names(v); ++v) {
        if (strcmp(field->names(v), name) == 0) {
            unsigned value = (unsigned)v;
            memcpy(at, &value, sizeof value);
            return REYES_CLI_OK;
        }
    }
    int used = snprintf(message, size, "unknown %s '%s'; valid:", field->kind, name);
    for (int v = 0; field->names(v) && used >= 0 && (size_t)used < size; ++v)
        used += snprintf(message + used, size - (size_t)used, " %s", field->names(v));
    return REYES_CLI_USAGE;
}

static int on_output(reyes_cli *cli, const char *value, char *message, size_t size)
{
    (void)message;
    (void)size;
    cli->output = value;
    return REYES_CLI_OK;
}

static int on_stats(reyes_cli *cli, const char *value, char *message, size_t size)
{
    (void)message;
    (void)size;
    cli->stats_path = value;
    cli->render.area_stats = 1; /* the JSON reports the micropolygons' areas */
    return REYES_CLI_OK;
}


static int on_size(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_wxh(value, &cli->render.width, &cli->render.height))
        return cli_usage_error(message, size, "--size '%s': expected WxH with sides 1..%s, e.g. 512x512",
                               value, "16384");
    return REYES_CLI_OK;
}

static int on_bucket(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_wxh(value, &cli->render.bucket_width, &cli->render.bucket_height))
        return cli_usage_error(message, size, "--bucket '%s': expected WxH with sides 1..%s, e.g. 64x64",
                               value, "16384");
    return REYES_CLI_OK;
}

/* bumps:AMPLITUDE or png:FILE:AMPLITUDE (the amplitude after the last ':'). */
static int on_displace(reyes_cli *cli, const char *value, char *message, size_t size)
{
    const char *last = strrchr(value, ':');
    int bumps = strncmp(value, "bumps:", 6) == 0, png = strncmp(value, "png:", 4) == 0;
    if (!last || (!bumps && !png) || (bumps && last != value + 5) || (png && last <= value + 4))
        return cli_usage_error(message, size, "--displace '%s': expected %s", value,
                               "bumps:AMPLITUDE or png:FILE:AMPLITUDE");
    if (!cli_parse_float(last + 1, &cli->render.displace_amplitude))
        return cli_usage_error(message, size, "--displace: amplitude '%s' is not a number%s", last + 1, "");
    cli->render.displace_mode = bumps ? REYES_DISPLACE_BUMPS : REYES_DISPLACE_MAP;
    if (png) {
        size_t n = (size_t)(last - (value + 4));
        if (n >= sizeof cli->displace_map)
            return cli_usage_error(message, size, "--displace: file name '%s' is too long%s", value, "");
        memcpy(cli->displace_map, value + 4, n);
        cli->displace_map[n] = '\0';
        cli->render.displace_map = cli->displace_map;
    }
    return REYES_CLI_OK;
}

static int on_motion(reyes_cli *cli, const char *value, char *message, size_t size)
{
    return cli_parse_float_list("--motion", value, cli->render.motion, 3, "dx,dy,dz", message, size);
}

/* ax,ay,az,DEG: a rotation about the axis through the camera target over
 * the shutter; the axis must have a length and the angle be within a turn
 * (each vertex moves linearly between its open and close positions). */
static int on_motion_rotate(reyes_cli *cli, const char *value, char *message, size_t size)
{
    float v[4];
    int status = cli_parse_float_list("--motion-rotate", value, v, 4, "ax,ay,az,DEG", message, size);
    if (status != REYES_CLI_OK)
        return status;
    double length = (double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2];
    if (!(length > 0.0) || !isfinite(length))
        return cli_usage_error(message, size, "--motion-rotate '%s': the axis must be finite and not zero%s",
                               value, "");
    if (!isfinite(v[3]) || fabsf(v[3]) > REYES_MAX_MOTION_ANGLE)
        return cli_usage_error(message, size, "--motion-rotate '%s': the angle must be in -360..360 degrees%s",
                               value, "");
    for (int k = 0; k < 3; ++k)
        cli->render.motion_axis[k] = v[k];
    cli->render.motion_angle_deg = v[3];
    return REYES_CLI_OK;
}

static int on_aperture(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_float(value, &cli->render.aperture) || cli->render.aperture < 0.0f)
        return cli_usage_error(message, size, "--aperture '%s': expected a lens radius >= 0%s", value, "");
    return REYES_CLI_OK;
}

static int on_focus(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_float(value, &cli->render.focus) || !(cli->render.focus > 0.0f))
        return cli_usage_error(message, size, "--focus '%s': expected a distance > 0%s", value, "");
    return REYES_CLI_OK;
}

static int on_time_samples(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_unsigned(value, REYES_MAX_SPP, &cli->render.time_samples)
        || cli->render.time_samples < 1)
        return cli_usage_error(message, size, "--time-samples '%s': expected 1..%s", value, "64");
    return REYES_CLI_OK;
}

static int on_blur_tile(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_unsigned(value, REYES_MAX_BLUR_TILE, &cli->render.blur_tile) || cli->render.blur_tile < 1)
        return cli_usage_error(message, size, "--blur-tile '%s': expected a tile side 1..%s", value, "8");
    return REYES_CLI_OK;
}

static int on_blur_permutations(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_unsigned(value, REYES_MAX_BLUR_PERMUTATIONS, &cli->render.blur_permutations)
        || cli->render.blur_permutations < 1)
        return cli_usage_error(message, size, "--blur-permutations '%s': expected 1..%s", value, "64");
    return REYES_CLI_OK;
}

static int on_bound(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_float(value, &cli->render.bound_px) || cli->render.bound_px < 0.5f)
        return cli_usage_error(message, size, "--bound '%s': expected pixels >= 0.5%s", value, "");
    cli->bound_given = 1;
    return REYES_CLI_OK;
}

static int on_epsilon(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_float(value, &cli->render.flat_epsilon)
        || !(cli->render.flat_epsilon >= 0.01f && cli->render.flat_epsilon <= REYES_MAX_EPSILON))
        return cli_usage_error(message, size, "--epsilon '%s': expected pixels in 0.01..%s", value,
                               "1000");
    cli->flatness_given = 1;
    return REYES_CLI_OK;
}

static int on_lambda(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_float(value, &cli->render.flat_lambda)
        || !(cli->render.flat_lambda >= 0.0f && cli->render.flat_lambda <= 1.0f))
        return cli_usage_error(message, size, "--lambda '%s': expected a weight in 0..1%s", value, "");
    cli->flatness_given = 1;
    return REYES_CLI_OK;
}

static int on_grid(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_unsigned(value, REYES_MAX_GRID, &cli->render.grid) || cli->render.grid < 2)
        return cli_usage_error(message, size, "--grid '%s': expected 2..%s", value, "32");
    cli->grid_given = 1;
    return REYES_CLI_OK;
}

static int on_shading_rate(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_float(value, &cli->render.shading_rate)
        || !(cli->render.shading_rate >= REYES_MIN_SHADING_RATE && cli->render.shading_rate <= REYES_MAX_SHADING_RATE))
        return cli_usage_error(message, size, "--shading-rate '%s': expected square pixels in %s", value,
                               "0.01..10000");
    cli->shading_rate_given = 1;
    return REYES_CLI_OK;
}

static int on_spp(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_unsigned(value, REYES_MAX_SPP, &cli->render.spp) || cli->render.spp < 1)
        return cli_usage_error(message, size, "--spp '%s': expected 1..%s", value, "64");
    return REYES_CLI_OK;
}

static int on_max_depth(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_unsigned(value, REYES_MAX_DEPTH, &cli->render.max_depth))
        return cli_usage_error(message, size, "--max-depth '%s': expected 0..%s", value, "40");
    return REYES_CLI_OK;
}

static int on_groups(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_unsigned(value, 4096, &cli->render.work_groups) || cli->render.work_groups < 1)
        return cli_usage_error(message, size, "--groups '%s': expected 1..%s", value, "4096");
    return REYES_CLI_OK;
}

static int on_fov(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_float(value, &cli->fov_deg) || !(cli->fov_deg > 0.5f && cli->fov_deg < 179.0f))
        return cli_usage_error(message, size, "--fov '%s': expected degrees in (0.5, 179)%s", value, "");
    return REYES_CLI_OK;
}

static int on_camera(reyes_cli *cli, const char *value, char *message, size_t size)
{
    int st = cli_parse_float_list("--camera", value, cli->camera, 6, "ex,ey,ez,ax,ay,az", message, size);
    if (st == REYES_CLI_OK)
        cli->has_camera = 1;
    return st;
}

/* A whole schedule label (perma_schedule_parse); the message is the parser's. */
static int on_schedule(reyes_cli *cli, const char *value, char *message, size_t size)
{
    perma_schedule schedule;
    perma_error error;
    if (perma_schedule_parse(value, &schedule, &error) != PERMA_OK)
        return cli_usage_error(message, size, "--schedule: %s%s", error.message, "");
    cli->render.schedule = schedule;
    return REYES_CLI_OK;
}

static int on_local_queue(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_unsigned(value, 65536, &cli->render.schedule.local_queue_items))
        return cli_usage_error(message, size, "--local-queue '%s': expected items 0..%s", value, "65536");
    return REYES_CLI_OK;
}

static int on_batch_limit(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_unsigned(value, 1u << 24, &cli->render.schedule.batch_limit) || cli->render.schedule.batch_limit < 1)
        return cli_usage_error(message, size, "--batch-limit '%s': expected items 1..%s", value, "16777216");
    return REYES_CLI_OK;
}

static int on_devices(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!value[0])
        return cli_usage_error(message, size, "--devices: expected a device list, e.g. %s%s", "0:0/2 or 0:0,1:0", "");
    cli->devices = value;
    return REYES_CLI_OK;
}

static int on_frames(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_unsigned(value, REYES_MAX_FRAMES, &cli->frames) || cli->frames < 1)
        return cli_usage_error(message, size, "--frames '%s': expected 1..%s", value, "100000");
    return REYES_CLI_OK;
}

static int on_orbit(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_float(value, &cli->orbit_deg) || fabsf(cli->orbit_deg) > 36000.0f)
        return cli_usage_error(message, size, "--orbit '%s': expected degrees in -36000..36000%s", value, "");
    cli->orbit_given = 1;
    return REYES_CLI_OK;
}

static int on_rank_timeout(reyes_cli *cli, const char *value, char *message, size_t size)
{
    if (!cli_parse_float(value, &cli->rank_timeout) || !(cli->rank_timeout >= 1.0f && cli->rank_timeout <= 1e6f))
        return cli_usage_error(message, size, "--rank-timeout '%s': expected seconds in 1..1e6%s", value, "");
    return REYES_CLI_OK;
}

const cli_option cli_options[] = {
    { "output", 'o', "FILE", on_output, "PNG to write (default reyes.png)", NULL },
    { "size", 0, "WxH", on_size, "image size in pixels (default 512x512)", NULL },
    { "bucket", 0, "WxH", on_bucket, "render in screen tiles of WxH pixels (default: one)", NULL },
    { "crack-fix", 0, "NAME", NULL,
      "stitch (default: fill cracks between grids), wedge (one pass; tiered only) or none",
      CHOICE("crack fix", crack_fix_name, render.crack_fix) },
    { "displace", 0, "KIND", on_displace,
      "bumps:AMPLITUDE or png:FILE:AMPLITUDE (gray PNG at the patch's u,v)", NULL },
    { "motion", 0, "dx,dy,dz", on_motion, "move every vertex by this over the shutter (motion blur)", NULL },
    { "motion-rotate", 0, "ax,ay,az,DEG", on_motion_rotate,
      "rotate by DEG (-360..360) about the axis through the camera target over the shutter, then --motion",
      NULL },
    { "aperture", 0, "R", on_aperture, "thin-lens radius in world units (depth of field; default 0)", NULL },
    { "focus", 0, "D", on_focus, "view depth in focus (default: distance to the camera target)", NULL },
    { "blur-algo", 0, "NAME", NULL, "blur sampling: interleaved (default), simple or bbox (docs/reyes.md)",
      CHOICE("blur algorithm", blur_algo_name, render.blur_algo) },
    { "blur-tile", 0, "K", on_blur_tile, "interleaved: tiles of KxK pixels, 1..8 (default 4)", NULL },
    { "blur-permutations", 0, "P", on_blur_permutations,
      "interleaved: permutations of a tile's tuples, 1..64 (default 8)", NULL },
    { "time-samples", 0, "N", on_time_samples, "time strata per pixel (default: spp)", NULL },
    { "bound", 0, "PX", on_bound,
      "dice patches whose screen bound is at most PX (default 8; tiered: grid - 1)", NULL },
    { "grid", 0, "N", on_grid,
      "dice every sub-patch N x N (2..32; alone: fixed grids); with --shading-rate: at most N per side "
      "(default 16)", NULL },
    { "show-grids", 0, NULL, NULL, "shade each grid in a false colour by its size (blue: 1 micropolygon .. red: "
      "(grid - 1)^2)", FLAG(render.show_grid_sizes) },
    { "shading-rate", 0, "R", on_shading_rate,
      "dice each sub-patch so a micropolygon is at most R square pixels (default 1; 0.01..10000)", NULL },
    { "subdivision", 0, "NAME", NULL, "when to stop splitting: bound (default: --bound) or tiered (flatness)",
      CHOICE("subdivision", subdivision_name, render.subdivision) },
    { "epsilon", 0, "PX", on_epsilon, "tiered: flatness tolerance in pixels (default 0.5)", NULL },
    { "lambda", 0, "L", on_lambda,
      "tiered: 0 geometric .. 1 parametric deviation weight (default 0.5)", NULL },
    { "spp", 0, "N", on_spp, "jittered samples per pixel (default 4)", NULL },
    { "max-depth", 0, "D", on_max_depth, "splits after which a patch is diced anyway (default 20)", NULL },
    { "camera", 0, "ex,ey,ez,ax,ay,az", on_camera, "eye and target (default: frame the scene)", NULL },
    { "fov", 0, "DEG", on_fov, "vertical field of view (default 40)", NULL },
    { "schedule", 0, "LABEL", on_schedule,
      "the five options below as one label, e.g. megakernel/stealing/round-robin+local32", NULL },
    { "technique", 0, "NAME", NULL, "megakernel (default), kernel-per-procedure or bounded-batches",
      CHOICE("technique", technique_name, render.schedule.technique) },
    { "strategy", 0, "NAME", NULL, "megakernel queues: shared (default), stealing, donation, stealing-donation",
      CHOICE("strategy", strategy_name, render.schedule.strategy) },
    { "victim", 0, "NAME", NULL, "stealing victim: random (default) or round-robin",
      CHOICE("victim", victim_name, render.schedule.victim) },
    { "local-queue", 0, "N", on_local_queue, "items per procedure in a per-group local queue (default 0)",
      NULL },
    { "batch-limit", 0, "N", on_batch_limit, "bounded-batches: items per host iteration (default 4096)", NULL },
    { "groups", 0, "N", on_groups, "persistent work-groups (default: as many as fit)", NULL },
    { "devices", 0, "LIST", on_devices,
      "spread buckets (or frames) over devices: 0:0,1:0, 0:0/2 (2 equal sub-devices), all", NULL },
    { "frames", 0, "N", on_frames, "render N frames NAME-0001.png ... (an orbit, or the motion)", NULL },
    { "orbit", 0, "DEG", on_orbit,
      "frames: turn the camera DEG about the vertical through the target (default 360, 0 with motion)", NULL },
    { "rank-timeout", 0, "S", on_rank_timeout,
      "mpirun: abort the job when a rank holds a bucket or frame S seconds (default 660)", NULL },
    { "coordinator-only", 0, NULL, NULL, "mpirun: rank 0 hands out and gathers but renders nothing (a head node)",
      FLAG(coordinator_only) },
    { "backface", 0, NULL, NULL, "cull patches that face away entirely", FLAG(render.backface_cull) },
    { "stats", 0, "FILE", on_stats, "write statistics as JSON", NULL },
    { "reference", 0, NULL, NULL, "also run the single-threaded C bound/split/dice and print its counts",
      FLAG(reference) },
    { "help", 'h', NULL, NULL, "show this help", FLAG(help) },
    { "version", 0, NULL, NULL, "show the version", FLAG(version) },
};

const size_t cli_option_count = COUNT_OF(cli_options);

int cli_option_apply(const cli_option *option, reyes_cli *cli, const char *value, char *message, size_t size)
{
    return option->handle ? option->handle(cli, value, message, size)
                          : set_field(cli, option->field, value, message, size);
}
