/*
 * Reyes renderer on perma: bicubic Bézier patches are bounded, split,
 * diced into micropolygon grids, shaded and rasterized by perma procedures
 * (see docs/reyes.md).  This header is the library used by the reyes-render
 * command and the tests.  Functions return a reyes_status and fill a
 * reyes_error; nothing here exits the process.
 */
#ifndef REYES_H
#define REYES_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "perma.h"
#include "reyes_procedures.h" /* the stage table: REYES_PROC_* */
#include "reyes_shared.h" /* REYES_DISPLACE_*, REYES_STAGES_* */

#define REYES_VERSION_STRING "0.1.0"
#define REYES_MESSAGE_MAX 1024

typedef enum reyes_status {
    REYES_OK = 0,
    REYES_ERR_ARGUMENT, /* an option or argument out of range */
    REYES_ERR_IO,       /* a file could not be read or written */
    REYES_ERR_FORMAT,   /* a model file is malformed; the message has file:line */
    REYES_ERR_NO_MEMORY,
    REYES_ERR_RUNTIME   /* perma failed; the message has its report */
} reyes_status;

typedef struct reyes_error {
    reyes_status status;
    char message[REYES_MESSAGE_MAX];
} reyes_error;

/* Set *error (may be NULL) and return status. */
reyes_status reyes_fail(reyes_error *error, reyes_status status, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* ---- Scenes: a list of bicubic Bézier patches with a color each. ---- */

#define REYES_MAX_PATCHES 10000000u /* refuse larger scenes (and file counts) */
/* Larger coordinates are refused by the loader: squared distances between
 * such points overflow single precision (about 3.4e38). */
#define REYES_MAX_COORDINATE 1e18f

typedef struct reyes_scene {
    float *points;      /* 16 control points per patch, x y z w (w = 1), row-major */
    uint32_t *colors;   /* RGBA8 per patch, red in the low byte */
    size_t patch_count;
    size_t capacity;
} reyes_scene;

void reyes_scene_init(reyes_scene *scene);
void reyes_scene_free(reyes_scene *scene);

/* Append one patch: cp[row][col][xyz]. */
reyes_status reyes_scene_add_patch(reyes_scene *scene, const float cp[4][4][3], uint32_t rgba,
                                   reyes_error *error);

/* Parse .bpt text (`name` is used in messages) or read a .bpt file, adding
 * its patches with color rgba.  Errors name the file and line. */
reyes_status reyes_scene_parse_bpt(reyes_scene *scene, const char *text, const char *name,
                                   uint32_t rgba, reyes_error *error);
reyes_status reyes_scene_load_bpt(reyes_scene *scene, const char *path, uint32_t rgba,
                                  reyes_error *error);

/* The built-in scene: two spheres, a torus and a ribbon, z up. */
reyes_status reyes_scene_add_builtin(reyes_scene *scene, reyes_error *error);

/* Shapes of the built-in scene, usable on their own (tests). */
reyes_status reyes_scene_add_sphere(reyes_scene *scene, const float center[3], float radius,
                                    uint32_t rgba, reyes_error *error);
reyes_status reyes_scene_add_torus(reyes_scene *scene, const float center[3], float major,
                                   float minor, uint32_t rgba, reyes_error *error);
reyes_status reyes_scene_add_ribbon(reyes_scene *scene, const float start[3], float length,
                                    float width, int pieces, uint32_t rgba, reyes_error *error);

/* Axis-aligned box of all control points (it contains the surfaces).
 * Returns 0 for an empty scene. */
int reyes_scene_bounds(const reyes_scene *scene, float lo[3], float hi[3]);

/* The scene's bulk: its control points but those far from the rest (more
 * than 64 times farther from the median point than 90% of the points;
 * e.g. one stray point 1e6 units from a teapot).  Returns 0 for an empty
 * scene. */
typedef struct reyes_bulk {
    float center[3];        /* the median point (per axis) */
    float keep_radius;      /* points farther from center are left out; may be infinite */
    float lo[3], hi[3];     /* the box of the points kept */
    size_t left_out;        /* control points left out */
    size_t first_left_out;  /* the first of them: patch first_left_out / 16, point % 16 */
} reyes_bulk;
int reyes_scene_bulk(const reyes_scene *scene, reyes_bulk *bulk);
/* Whether the bulk holds a point. */
int reyes_bulk_holds(const reyes_bulk *bulk, const float point[3]);

/* A distinct color for the n-th model. */
uint32_t reyes_model_color(unsigned n);

#define REYES_RGBA(r, g, b) ((uint32_t)(r) | ((uint32_t)(g) << 8) | ((uint32_t)(b) << 16) | 0xff000000u)

/* ---- Camera ---- */

typedef struct reyes_camera {
    float eye[3];
    float at[3];
    float fov_deg;     /* vertical field of view */
} reyes_camera;

/* Place the camera so every control point of the scene's bulk is in view
 * (fov_deg and aspect = width / height given); points far from the rest
 * (reyes_scene_bulk) are not framed. */
reyes_status reyes_camera_frame(const reyes_scene *scene, float fov_deg, float aspect,
                                reyes_camera *camera, reyes_error *error);

/* Row-major view-projection matrix: clip = m * (x y z 1), clip.w is the
 * depth along the view direction.  Up is +z unless the view is vertical. */
reyes_status reyes_camera_matrix(const reyes_camera *camera, float aspect, float near_w,
                                 float m[16], reyes_error *error);

/* Clip w of the near plane for a scene seen by a camera: 1e-4 of the
 * median depth of the control points in front of it, or of the scene's
 * radius if that is smaller. */
float reyes_near_plane(const reyes_scene *scene, const reyes_camera *camera);

/* Pixel position (y down) and depth of a world point; 0 if behind the eye. */
int reyes_camera_project(const float m[16], unsigned width, unsigned height, const float x[3],
                         float *px, float *py, float *depth);

/* ---- Rendering ---- */

enum { REYES_CRACK_FIX_NONE, REYES_CRACK_FIX_STITCH, REYES_CRACK_FIX_WEDGE, REYES_CRACK_FIX_POLYLINE };

/* Subdivision criteria: the values of reyes_shared.h. */
#define REYES_MAX_EPSILON 1000.0f

/* Spreading one image's buckets over several renderers (devices, MPI
 * ranks; examples/reyes/scale/reyes_farm.c and docs/scale-out.md): a render given a bucket source
 * renders the buckets next() hands out, until it returns 0, instead of
 * all of them in order, and calls done() after each.  Buckets are
 * numbered row by row from 0 (columns = ceil(width / bucket_width)); an
 * unbucketed image is bucket 0.  Pixels of buckets it did not render are
 * left 0.  Each renderer first makes the crack-stitching plan of the
 * whole image itself (a bound/split pass; deterministic), so any renderer
 * may render any bucket and the pieces make the one-renderer image, byte
 * for byte, on devices of one OpenCL implementation. */
struct reyes_image;
typedef struct reyes_bucket_source {
    /* The next bucket into *bucket; 0 when there is none.  Called from
     * reyes_render's thread between buckets; it may block. */
    int (*next)(void *user, unsigned *bucket);
    /* After `bucket` (pixels [x0,x1) x [y0,y1)) is resolved into *image;
     * may be NULL.  A status other than REYES_OK ends the render with it
     * (fill *error). */
    reyes_status (*done)(void *user, unsigned bucket, const struct reyes_image *image, unsigned x0,
                         unsigned y0, unsigned x1, unsigned y1, reyes_error *error);
    void *user;
} reyes_bucket_source;

typedef struct reyes_options {
    unsigned width, height;
    float bound_px;       /* dice below this screen bound (default 8) */
    unsigned grid;        /* grid vertices per side (default 16); with a shading rate, the most */
    /* Shading-rate dicing (docs/reyes-dicing.md): 0 (default) dices every
     * sub-patch grid x grid; R > 0 dices each to the fewest vertices along
     * u and v (at most grid) whose micropolygons are at most R pixels in
     * area on screen, and splits a sub-patch until that fits (instead of
     * at bound_px; the tiered criterion's flatness still applies).  Not
     * with REYES_CRACK_FIX_WEDGE; the C reference refuses it. */
    float shading_rate;
    /* 1: shade each grid in a false colour by its micropolygons' count
     * (blue: 1, green, yellow, red: (grid - 1)^2) instead of its model's
     * colour, to see the dicing; 0 (default). */
    int show_grid_sizes;
    /* When to stop splitting: REYES_SUBDIVISION_BOUND (default) dices a
     * sub-patch whose screen bound is at most bound_px;
     * REYES_SUBDIVISION_TIERED (docs/reyes-dicing.md) dices one whose edge and
     * inner control-net curves are all within flat_epsilon pixels of
     * straight, uniformly parametrised lines (the geometric and the full,
     * parametric deviation mixed by flat_lambda in 0..1) and whose bound
     * is at most flat_bound_px (0, the default: grid - 1 pixels, so
     * micropolygons of about a pixel at most). */
    unsigned subdivision;
    float flat_epsilon;   /* pixels (default 0.5) */
    float flat_lambda;    /* 0: geometric only .. 1: full deviation (default 0.5) */
    float flat_bound_px;  /* 0 or 0.5..1e6 */
    unsigned spp;         /* samples per pixel (default 4) */
    unsigned max_depth;   /* split depth that forces dicing (default 20) */
    int backface_cull;    /* default 0: the models have open, two-sided parts */
    /* 1 (default): with a shading rate (undisplaced, unblurred, not
     * wedges), dice skips a small grid whose samples already all hold a
     * nearer surface (docs/reyes-dicing.md, "Occlusion culling"); the image is
     * the same, but which grids are skipped depends on the order they
     * run in, so the micropolygon counts depend on the schedule.  0: off
     * (counts that match the C reference and every schedule). */
    unsigned occlusion_cull;
    float cull_margin;    /* frustum margin, fraction of the viewport (default 0.05) */
    uint32_t background;  /* RGBA8 of empty samples */
    /* REYES_STAGES_ALL (default); REYES_STAGES_GEOMETRY or _SUBDIVIDE stop
     * early so stages can be timed by difference (reyes_shared.h). */
    unsigned stages;
    /* Screen-space buckets: render the image in tiles of at most
     * bucket_width x bucket_height pixels, one perma run each, culling the
     * patches outside the tile; 0 x 0 (default) renders the whole image at
     * once.  The image is the same either way. */
    unsigned bucket_width, bucket_height;
    /* NULL (default): render every bucket; else the buckets it hands out. */
    const reyes_bucket_source *bucket_source;
    /* 1: the image also keeps every sample (reyes_image.samples), for
     * comparisons sample by sample; 0 (default): only the pixels. */
    int keep_samples;
    /* 1: tally the micropolygons' areas on screen in the statistics
     * (reyes_stats.micropolygon_area*; unblurred full renders); 0
     * (default): not (a few atomics per grid saved). */
    int area_stats;
    /* Cracks between grids diced at different rates (T-junctions) and
     * between base patches: REYES_CRACK_FIX_STITCH (default) fills them
     * with zipper strips (two passes: subdivide, then dice and stitch),
     * REYES_CRACK_FIX_WEDGE closes them in one pass without communication
     * between patches (needs REYES_SUBDIVISION_TIERED and no displacement:
     * every edge settles on a flat segment of its base patch's line and
     * both sides reach the polyline of its curve at grid - 1 steps with
     * wedge strips; docs/reyes-dicing.md),
     * REYES_CRACK_FIX_POLYLINE closes them in one pass without
     * communication with a shading rate (not fixed grids, no
     * displacement: both sides of every edge put the polyline of a segment
     * of its line they choose alone on it, and the side with a corner
     * inside one of its pieces fills the T-junction; reyes-render's
     * default with a shading rate), REYES_CRACK_FIX_NONE leaves them. */
    unsigned crack_fix;
    /* Displacement along the normal (docs/reyes-effects.md): REYES_DISPLACE_NONE
     * (default), _BUMPS (procedural noise bumps of height 0..amplitude) or
     * _MAP (grayscale PNG `displace_map`, bilinear at the base patch's
     * (u,v), white = amplitude).  Amplitude 0 renders as no displacement. */
    unsigned displace_mode;
    float displace_amplitude;   /* world units */
    const char *displace_map;   /* PNG path for REYES_DISPLACE_MAP */
    /* Motion blur and depth of field: every vertex
     * moves by motion[] (world units) over the shutter; a thin lens of
     * radius `aperture` (world units) focused at view depth `focus` (0:
     * the camera's target).  time_samples: time strata per pixel (0: spp).
     * Zero motion and aperture render exactly as without the feature.
     * motion_angle_deg (|angle| <= 360) rotates the scene about
     * motion_axis (right-handed, any length but 0) through the camera's
     * target over the shutter, before the translation: each vertex moves
     * linearly from p to R (p - target) + target + motion, its own motion
     * vector.  Needs a renderer created with a rotation (per-vertex motion
     * items, reyes_renderer_create). */
    float motion[3];
    float motion_axis[3];
    float motion_angle_deg;
    float aperture;
    float focus;
    unsigned time_samples;
    /* How samples get their time and lens position (docs/reyes-effects.md):
     * REYES_BLUR_SIMPLE, _INTERLEAVED (default) or _BBOX; interleaved uses
     * tiles of blur_tile x blur_tile pixels (default 4) and
     * blur_permutations permutations of their slots (default 8). */
    unsigned blur_algo;
    unsigned blur_tile;
    unsigned blur_permutations;
    /* Scheduling, passed to perma_config when the renderer is created;
     * 0 = the runtime's default, except group_size: 0 = 8 work-items on a
     * CPU device (one runs a group's work-items one after another, and the
     * dice and rasterize procedures do their own SIMD), else 64. */
    unsigned work_groups;
    unsigned group_size;
    perma_schedule schedule;        /* perma_config.schedule; zero = megakernel/shared */
    double time_limit;
    /* The OpenCL device (reyes_renderer_create); NULL (default): the
     * first of PERMA_DEVICE, or 0:0. */
    const perma_device_ref *device;
    /* The progress of each perma run (perma_config.progress, every
     * progress_interval seconds, 0: the runtime's default), passed when
     * the renderer is created; called on the rendering thread.  NULL
     * (default): none. */
    void (*progress)(void *user, const perma_progress *progress);
    void *progress_user;
    double progress_interval;
    /* perma_config.trace_path, passed when the renderer is created: the
     * Chrome trace file every perma run of the renderer adds its batches
     * to.  NULL (default): PERMA_TRACE's, or none. */
    const char *trace_path;
} reyes_options;

void reyes_options_init(reyes_options *options);

/* Limits the options are checked against. */
#define REYES_MAX_SIZE 16384u
#define REYES_MAX_GRID 32u
#define REYES_MIN_SHADING_RATE 0.01f
#define REYES_MAX_SHADING_RATE 10000.0f
#define REYES_MAX_SPP 64u
#define REYES_MAX_DEPTH 40u
#define REYES_MAX_BUCKETS 1048576u
#define REYES_MAX_BLUR_TILE 8u
#define REYES_MAX_BLUR_PERMUTATIONS 64u
#define REYES_MAX_MOTION_ANGLE 360.0f

reyes_status reyes_options_check(const reyes_options *options, reyes_error *error);

/* "simple", "interleaved", "bbox"; NULL past the last algorithm. */
const char *reyes_blur_algo_name(unsigned algo);
/* The REYES_BLUR_* named `name`; 0 if there is none. */
int reyes_blur_algo_parse(const char *name, unsigned *algo);

typedef struct reyes_image {
    unsigned width, height;
    uint8_t *rgb;       /* width * height * 3, rows top to bottom */
    uint8_t *coverage;  /* per pixel: samples that hit a surface */
    /* With reyes_options.keep_samples (else NULL): spp words per pixel,
     * pixels row by row, each (bits of the depth << 32) | RGBA8 of the
     * nearest surface (depth: the positive view distance, as a float's
     * bits) or REYES_EMPTY_SAMPLE. */
    uint64_t *samples;
    unsigned spp;
} reyes_image;

#define REYES_EMPTY_SAMPLE UINT64_MAX

void reyes_image_free(reyes_image *image);

/* The procedures, in the order of the stage table (reyes_procedures.h;
 * dice rasterizes the grids it dices itself). */
#define REYES_PROC_ENUM(e, name, item, priority, emits) REYES_PROC_##e,
enum { REYES_PROCEDURES(REYES_PROC_ENUM) REYES_PROC_COUNT };
#undef REYES_PROC_ENUM

typedef struct reyes_stats {
    uint64_t patches_in;
    uint64_t splits;
    /* Why bound split (they add up to splits): the screen bound, the edge
     * or inner tier of the tiered criterion, the near plane. */
    uint64_t split_bound, split_edge, split_inner, split_near;
    uint64_t culled;
    uint64_t grids;
    uint64_t forced_dice;     /* grids diced because of the depth limit */
    uint64_t micropolygons;
    uint64_t samples_written;
    uint64_t stitches;        /* edges stitched (stitch items) */
    uint64_t fillers;         /* crack-filling triangles in front of the eye */
    uint64_t occluded;        /* grids dice skipped as hidden (occlusion_cull; schedule-dependent) */
    /* With reyes_options.area_stats (unblurred full renders): the
     * micropolygons' total area on screen in square pixels and how many
     * fell in each area bin (reyes_area_bin_lower; mean and percentiles:
     * reyes_stats_area_mean, reyes_stats_area_percentile). */
    double micropolygon_area;
    uint64_t micropolygon_area_bins[REYES_AREA_BINS];
    size_t peak_queue_bytes;  /* largest of any run */
    double seconds;           /* perma_run wall time (sum over buckets) */
    /* Buckets: columns x rows, and each bucket's peak queue memory (row
     * by row; allocated only for bucketed renders, else NULL and the one
     * bucket's peak is peak_queue_bytes).  Free with reyes_stats_free. */
    unsigned bucket_columns, bucket_rows;
    size_t *bucket_peak_queue_bytes;
    /* The runtime's statistics, summed over the buckets' runs (peaks and
     * capacities: the largest). */
    perma_stats run;
    perma_procedure_stats procedures[REYES_PROC_COUNT];
    /* How the runtime chose run.work_groups (perma_stats.work_groups_reason,
     * copied: run.work_groups_reason is NULL here). */
    char work_groups_reason[160];
} reyes_stats;

/* Free what a render allocated in *stats (the per-bucket list). */
void reyes_stats_free(reyes_stats *stats);

/* The smallest area (square pixels) of micropolygon area bin `bin`: 0 for
 * bin 0, then half octaves 2^e and 1.5 * 2^e from 2^-10 (bin 1) to 32
 * (the last bin, up from there). */
double reyes_area_bin_lower(unsigned bin);

/* The mean micropolygon area, and the area below which a `fraction`
 * (0..1) of them fall, interpolated geometrically inside its bin (the
 * last bin's lower end when it falls there); 0 without micropolygons. */
double reyes_stats_area_mean(const reyes_stats *stats);
double reyes_stats_area_percentile(const reyes_stats *stats, double fraction);

/* A perma runtime with the Reyes procedures registered (for options->grid
 * and the scheduling fields: group_size, work_groups, schedule,
 * time_limit, progress; the other options may change per render).  With options->motion_angle_deg not 0 the renderer
 * carries a clip-space motion per micropolygon vertex (112-byte items
 * instead of 64), which renders with a rotation need; it renders
 * everything else too, to the same bytes. */
typedef struct reyes_renderer reyes_renderer;

reyes_status reyes_renderer_create(const reyes_options *options, reyes_renderer **out,
                                   reyes_error *error);
void reyes_renderer_destroy(reyes_renderer *renderer);

/* Bytes of one diced grid of shaded vertices (struct reyes_grid of
 * reyes_grid.cl, in dice's __local scratch) for a grid size, with or
 * without the per-vertex motion of a renderer made for a rotation. */
size_t reyes_grid_item_bytes(unsigned grid, int vertex_motion);

/* One line describing the OpenCL device and groups. */
const char *reyes_renderer_device(const reyes_renderer *renderer);

/* Render the scene; *image is allocated (free with reyes_image_free).
 * stats may be NULL. */
reyes_status reyes_render(reyes_renderer *renderer, const reyes_scene *scene,
                          const reyes_camera *camera, const reyes_options *options,
                          reyes_image *image, reyes_stats *stats, reyes_error *error);

/* ---- Output ----
 * Every output file is written whole or not at all (perma_output in
 * perma.h): a full disk or a failed write leaves no partial file and an
 * earlier file at the path unchanged, and the message names the path and
 * the reason. */

/* Fills `out` with `data` (what the writer expects), or fails with a message. */
typedef reyes_status (*reyes_output_writer)(FILE *out, const void *data, reyes_error *error);
typedef struct reyes_output_file {
    const char *path;
    reyes_output_writer write;
    const void *data;
} reyes_output_file;

/* Write `count` files together: each is written and synced beside its
 * path first, and only when all are complete are they renamed into place,
 * so a failure leaves none of them changed (the message says so). */
reyes_status reyes_write_outputs(const reyes_output_file *files, size_t count, reyes_error *error);

/* Whether `path` can be written (perma_output_check), before work whose
 * result goes there; `what` names it in the message ("--stats"). */
reyes_status reyes_check_output(const char *path, const char *what, reyes_error *error);

/* The PNG writer: data is a const reyes_image *. */
reyes_status reyes_png_writer(FILE *out, const void *image, reyes_error *error);
reyes_status reyes_write_png(const char *path, const reyes_image *image, reyes_error *error);

/* A grayscale image read from a PNG of any format (converted to gray). */
typedef struct reyes_gray_map {
    unsigned width, height;
    uint8_t *gray;      /* width * height, rows top to bottom */
} reyes_gray_map;

/* Errors name the file. */
reyes_status reyes_read_gray_png(const char *path, reyes_gray_map *map, reyes_error *error);
void reyes_gray_map_free(reyes_gray_map *map);

/* Statistics as a JSON object (the keys documented in docs/reyes.md). */
reyes_status reyes_write_stats_json(FILE *out, const reyes_stats *stats,
                                    const reyes_options *options, reyes_error *error);
reyes_status reyes_save_stats_json(const char *path, const reyes_stats *stats,
                                   const reyes_options *options, reyes_error *error);
/* The statistics writer for reyes_write_outputs: data is a const reyes_stats_output *. */
typedef struct reyes_stats_output {
    const reyes_stats *stats;
    const reyes_options *options;
} reyes_stats_output;
reyes_status reyes_stats_writer(FILE *out, const void *stats_output, reyes_error *error);

#endif
