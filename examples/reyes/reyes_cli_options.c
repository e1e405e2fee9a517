/*
 * The options of reyes-render: every option is one row of the table in
 * reyes_cli_describe (name, value, target, range, help) for the engine of
 * perma's programs (perma_cli.h), which parses the value into the target
 * or says what it expected, and writes --help from the rows.  Options
 * whose value is not a single number, size or name have a parser here.
 * Technique, strategy and victim names are the runtime's (perma_*_name),
 * so new ones work here without a change.  The parse and the checks of
 * options that depend on each other: reyes_cli.c.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "reyes_cli_internal.h"

#define REYES_MAX_FRAMES 100000u

static const char *const crack_fix_names[] = { "none", "stitch", "wedge", "polyline", NULL }; /* REYES_CRACK_FIX_* */
static const char *const off_on_names[] = { "off", "on", NULL };
static const char *const subdivision_names[] = { "bound", "tiered", NULL };          /* REYES_SUBDIVISION_* */

/* Models: every operand, into cli->models (room for argc of them). */
static int add_model(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    (void)complaint;
    (void)size;
    reyes_cli *cli = option->target;
    cli->models[cli->model_count++] = value;
    return 0;
}

/* As many comma-separated numbers into the target floats as the
 * argument's shape has ("dx,dy,dz": 3). */
static int parse_floats(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    size_t count = 1;
    for (const char *c = option->argument; *c; ++c)
        count += *c == ',';
    return perma_cli_floats(value, option->target, count, option->argument, complaint, size);
}

/* ex,ey,ez,ax,ay,az: points within the coordinates a model may have
 * (beyond them the renderer's single-precision arithmetic overflows). */
static int parse_camera(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    double v[6];
    if (perma_cli_doubles(value, v, 6, option->argument, complaint, size) != 0)
        return 1;
    for (int k = 0; k < 6; ++k) {
        if (fabs(v[k]) > (double)REYES_MAX_COORDINATE) {
            snprintf(complaint, size, "the %s's %c, %g, is beyond +-%g, the supported range of coordinates",
                     k < 3 ? "eye" : "target", "xyz"[k % 3], v[k], (double)REYES_MAX_COORDINATE);
            return 1;
        }
    }
    float *camera = option->target;
    for (int k = 0; k < 6; ++k)
        camera[k] = (float)v[k];
    return 0;
}

/* bumps:AMPLITUDE or png:FILE:AMPLITUDE (the amplitude after the last ':'). */
static int parse_displace(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    reyes_cli *cli = option->target;
    const char *last = strrchr(value, ':');
    int bumps = strncmp(value, "bumps:", 6) == 0, png = strncmp(value, "png:", 4) == 0;
    size_t n = png && last ? (size_t)(last - (value + 4)) : 0;
    float amplitude;
    if (!last || (!bumps && !png) || (bumps && last != value + 5) || (png && last <= value + 4))
        snprintf(complaint, size, "expected bumps:AMPLITUDE or png:FILE:AMPLITUDE");
    else if (perma_cli_floats(last + 1, &amplitude, 1, "AMPLITUDE", complaint, size) != 0)
        snprintf(complaint, size, "amplitude '%s' is not a number", last + 1);
    else if (n >= sizeof cli->displace_map)
        snprintf(complaint, size, "the file name is too long");
    else {
        cli->render.displace_amplitude = amplitude;
        cli->render.displace_mode = bumps ? REYES_DISPLACE_BUMPS : REYES_DISPLACE_MAP;
        if (png) {
            memcpy(cli->displace_map, value + 4, n);
            cli->displace_map[n] = '\0';
            cli->render.displace_map = cli->displace_map;
        }
        return 0;
    }
    return 1;
}

/* ax,ay,az,DEG: a rotation about the axis through the camera target over
 * the shutter; the axis must have a length and the angle be within a turn
 * (each vertex moves linearly between its open and close positions). */
static int parse_motion_rotate(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    reyes_options *render = option->target;
    float v[4];
    if (perma_cli_floats(value, v, 4, option->argument, complaint, size) != 0)
        return 1;
    double length = (double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2];
    if (!(length > 0.0) || !isfinite(length)) {
        snprintf(complaint, size, "the axis must be finite and not zero");
        return 1;
    }
    if (fabsf(v[3]) > REYES_MAX_MOTION_ANGLE) {
        snprintf(complaint, size, "the angle must be in -360..360 degrees");
        return 1;
    }
    memcpy(render->motion_axis, v, sizeof render->motion_axis);
    render->motion_angle_deg = v[3];
    return 0;
}

/* A whole schedule label (perma_schedule_parse); the complaint is the
 * parser's, without its "schedule 'LABEL': " (the engine names the value). */
static int parse_schedule(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    perma_error error;
    if (perma_schedule_parse(value, option->target, &error) == PERMA_OK)
        return 0;
    const char *why = strstr(error.message, "': ");
    snprintf(complaint, size, "%s", why ? why + 3 : error.message);
    return 1;
}

static int parse_devices(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    if (!value[0]) {
        snprintf(complaint, size, "expected a device list, e.g. 0:0/2 or 0:0,1:0");
        return 1;
    }
    *(const char **)option->target = value;
    return 0;
}

void reyes_cli_describe(reyes_cli *cli, const char *program, reyes_cli_description *d)
{
    reyes_options *r = &cli->render;
    const perma_cli_option rows[] = {
        { PERMA_CLI_TEXT("output", "FILE", &cli->output, "PNG to write (default reyes.png)"), .short_name = 'o' },
        { PERMA_CLI_SIZE("size", "WxH", cli->size, 1, REYES_MAX_SIZE, "image size in pixels (default 512x512)") },
        { PERMA_CLI_SIZE("bucket", "WxH", cli->bucket, 1, REYES_MAX_SIZE,
                         "render in screen tiles of WxH pixels (default: one)") },
        { PERMA_CLI_CHOICE("crack-fix", "NAME", &r->crack_fix, crack_fix_names,
                           "how cracks between grids are filled (default: polyline with a shading rate and no "
                           "displacement, else stitch; wedge: fixed grids, tiered only)"),
          .given = &cli->crack_fix_given },
        { PERMA_CLI_CUSTOM("displace", "KIND", parse_displace, cli,
                           "bumps:AMPLITUDE or png:FILE:AMPLITUDE (gray PNG at the patch's u,v)") },
        { PERMA_CLI_CUSTOM("motion", "dx,dy,dz", parse_floats, r->motion,
                           "move every vertex by this over the shutter (motion blur)") },
        { PERMA_CLI_CUSTOM("motion-rotate", "ax,ay,az,DEG", parse_motion_rotate, r,
                           "rotate by DEG (-360..360) about the axis through the camera target over the shutter, "
                           "then --motion") },
        { PERMA_CLI_FLOAT("aperture", "R", &r->aperture, 0, INFINITY,
                          "thin-lens radius in world units (depth of field; default 0)") },
        { PERMA_CLI_FLOAT("focus", "D", &r->focus, 0, INFINITY,
                          "view depth in focus (default: distance to the camera target)"),
          .open = PERMA_CLI_ABOVE_LOW },
        { PERMA_CLI_CHOICE_OF("blur-algo", "NAME", &r->blur_algo, reyes_blur_algo_name,
                              "blur sampling (default interleaved; docs/reyes-effects.md)") },
        { PERMA_CLI_WHOLE("blur-tile", "K", &r->blur_tile, 1, REYES_MAX_BLUR_TILE,
                          "interleaved: tiles of KxK pixels (default 4)") },
        { PERMA_CLI_WHOLE("blur-permutations", "P", &r->blur_permutations, 1, REYES_MAX_BLUR_PERMUTATIONS,
                          "interleaved: permutations of a tile's tuples (default 8)") },
        { PERMA_CLI_WHOLE("time-samples", "N", &r->time_samples, 1, REYES_MAX_SPP,
                          "time strata per pixel (default: spp)") },
        { PERMA_CLI_FLOAT("bound", "PX", &r->bound_px, 0.5, INFINITY,
                          "dice patches whose screen bound is at most PX (default 8; tiered: grid - 1)"),
          .given = &cli->bound_given },
        { PERMA_CLI_WHOLE("grid", "N", &r->grid, 2, REYES_MAX_GRID,
                          "dice every sub-patch N x N (alone: fixed grids); with --shading-rate: at most N per side "
                          "(default 16)"),
          .given = &cli->grid_given },
        { PERMA_CLI_FLAG("show-grids", &r->show_grid_sizes,
                         "shade each grid in a false colour by its size (blue: 1 micropolygon .. red: (grid - 1)^2)") },
        { PERMA_CLI_FLOAT("shading-rate", "R", &r->shading_rate, REYES_MIN_SHADING_RATE, REYES_MAX_SHADING_RATE,
                          "dice each sub-patch so a micropolygon is at most R square pixels (default 1)"),
          .given = &cli->shading_rate_given },
        { PERMA_CLI_CHOICE("subdivision", "NAME", &r->subdivision, subdivision_names,
                           "when to stop splitting: at --bound (default) or tiered (flatness)") },
        { PERMA_CLI_FLOAT("epsilon", "PX", &r->flat_epsilon, 0.01, REYES_MAX_EPSILON,
                          "tiered: flatness tolerance in pixels (default 0.5)"),
          .given = &cli->flatness_given },
        { PERMA_CLI_FLOAT("lambda", "L", &r->flat_lambda, 0, 1,
                          "tiered: 0 geometric .. 1 parametric deviation weight (default 0.5)"),
          .given = &cli->flatness_given },
        { PERMA_CLI_WHOLE("spp", "N", &r->spp, 1, REYES_MAX_SPP, "jittered samples per pixel (default 4)") },
        { PERMA_CLI_WHOLE("max-depth", "D", &r->max_depth, 0, REYES_MAX_DEPTH,
                          "splits after which a patch is diced anyway (default 20)") },
        { PERMA_CLI_CUSTOM("camera", "ex,ey,ez,ax,ay,az", parse_camera, cli->camera,
                           "eye and target (default: frame the scene)"),
          .given = &cli->has_camera },
        { PERMA_CLI_FLOAT("fov", "DEG", &cli->fov_deg, 0.5, 179, "vertical field of view (default 40)"),
          .open = PERMA_CLI_ABOVE_LOW | PERMA_CLI_BELOW_HIGH },
        { PERMA_CLI_CUSTOM("schedule", "LABEL", parse_schedule, &r->schedule,
                           "the five options below as one label, e.g. megakernel/stealing/round-robin+local32") },
        { PERMA_CLI_CHOICE_OF("technique", "NAME", &r->schedule.technique, perma_cli_technique_name,
                              "how perma runs the procedures (default megakernel)") },
        { PERMA_CLI_CHOICE_OF("strategy", "NAME", &r->schedule.strategy, perma_cli_strategy_name,
                              "megakernel: how its groups share the queues (default shared)") },
        { PERMA_CLI_CHOICE_OF("victim", "NAME", &r->schedule.victim, perma_cli_victim_name,
                              "stealing: whom a group steals from (default random)") },
        { PERMA_CLI_WHOLE("local-queue", "N", &r->schedule.local_queue_items, 0, PERMA_MAX_LOCAL_QUEUE_ITEMS,
                          "items per procedure in a per-group local queue (default 0)") },
        { PERMA_CLI_WHOLE("batch-limit", "N", &r->schedule.batch_limit, 1, 1u << 24,
                          "bounded-batches: items per host iteration (default 4096)") },
        { PERMA_CLI_WHOLE("groups", "N", &r->work_groups, 1, 4096, "persistent work-groups (default: as many as fit)") },
        { PERMA_CLI_CUSTOM("devices", "LIST", parse_devices, &cli->devices,
                           "spread buckets (or frames) over devices: 0:0,1:0, 0:0/2 (2 equal sub-devices), all") },
        { PERMA_CLI_WHOLE("frames", "N", &cli->frames, 1, REYES_MAX_FRAMES,
                          "render N frames NAME-0001.png ... (an orbit, or the motion)") },
        { PERMA_CLI_FLOAT("orbit", "DEG", &cli->orbit_deg, -36000, 36000,
                          "frames: turn the camera DEG about the vertical through the target (default 360, 0 with "
                          "motion)"),
          .given = &cli->orbit_given },
        { PERMA_CLI_FLOAT("rank-timeout", "S", &cli->rank_timeout, 1, 1e6,
                          "mpirun: end the job when a rank holds a bucket or frame S seconds, or rank 0 is silent "
                          "that long (default 660)") },
        { PERMA_CLI_FLAG("coordinator-only", &cli->coordinator_only,
                         "mpirun: rank 0 hands out and gathers but renders nothing (a head node)") },
        { PERMA_CLI_FLAG("backface", &r->backface_cull, "cull patches that face away entirely") },
        { PERMA_CLI_CHOICE("occlusion", "on|off", &r->occlusion_cull, off_on_names,
                           "skip small grids hidden by what is already drawn (default on; shading rate only)") },
        { PERMA_CLI_TEXT("stats", "FILE", &cli->stats_path, "write statistics as JSON") },
        { PERMA_CLI_TEXT("trace", "FILE", &r->trace_path,
                         "write every perma run's batches to FILE as a Chrome trace (perma-trace-to-svg reads it; "
                         "under mpirun each rank writes FILE with -rankN before its extension)") },
        { PERMA_CLI_FLAG("progress", &cli->progress, "show the progress line on stderr even when it is not a "
                                                     "terminal (under mpirun: rank 0's, for the whole job)") },
        { PERMA_CLI_FLAG("quiet", &cli->quiet, "print nothing but errors (no progress line, no summary)"),
          .short_name = 'q' },
        { PERMA_CLI_FLAG("reference", &cli->reference,
                         "also run the single-threaded C bound/split/dice and print its counts") },
    };
    _Static_assert(sizeof rows / sizeof rows[0] <= REYES_CLI_ROWS, "REYES_CLI_ROWS holds the table");
    memcpy(d->rows, rows, sizeof rows);
    d->models = (perma_cli_option){ PERMA_CLI_CUSTOM(NULL, "MODEL.bpt", add_model, cli, NULL) };
    d->table = (perma_cli_table){ "options", d->rows, sizeof rows / sizeof rows[0] };
    d->cli = (perma_cli){
        .program = program,
        .synopsis = "[MODEL.bpt ...] [options]",
        .about = "Render bicubic Bezier patch models (.bpt) with a Reyes pipeline of perma\n"
                 "procedures; with no model, a built-in scene.",
        .tables = &d->table,
        .table_count = 1,
        .operand = &d->models,
        .notes = "exit status: 0 ok, 1 rendering or file error, 2 bad usage",
        .quiet = 1,
    };
}
