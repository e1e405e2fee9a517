/* The device parameters of a render (struct reyes_params): the camera
 * matrix, the lighting, the subdivision and dicing settings, and motion
 * blur and depth of field. */
#include <math.h>
#include <string.h>

#include "reyes_look.h"
#include "reyes_render_internal.h"

/* (R - I) for the rotation by `deg` degrees about `axis` (Rodrigues),
 * in double: the part of a vertex's motion that depends on its position. */
static void rotation_minus_identity(const float axis[3], float deg, double out[9])
{
    double a[3], length = 0.0;
    for (int k = 0; k < 3; ++k)
        length += (double)axis[k] * axis[k];
    length = sqrt(length);
    for (int k = 0; k < 3; ++k)
        a[k] = axis[k] / length;
    double theta = deg * (3.14159265358979323846 / 180.0), c = cos(theta), s = sin(theta);
    const double cross[9] = {0.0, -a[2], a[1], a[2], 0.0, -a[0], -a[1], a[0], 0.0};
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k)
            out[r * 3 + k] = (c - 1.0) * (r == k) + s * cross[r * 3 + k] + (1.0 - c) * a[r] * a[k];
}

/* A vertex at world p moves by (R - I)(p - target) + motion over the
 * shutter, clip-space motion M3 (R - I) p + M3 (motion - (R - I) target)
 * (M3 the matrix without translation; rows x, y, w): an affine map of p,
 * motion_rows.  Without a rotation its linear part is 0 and the constant
 * column is the uniform motion, computed as before. */
static void set_motion(const reyes_camera *camera, const reyes_options *o, struct reyes_params *p)
{
    const float *m = p->view_proj;
    double rot[9] = {0};
    p->motion_rotates = o->motion_angle_deg != 0.0f;
    if (p->motion_rotates)
        rotation_minus_identity(o->motion_axis, o->motion_angle_deg, rot);
    float d[3];
    for (int k = 0; k < 3; ++k) {
        double moved = rot[k * 3] * camera->at[0] + rot[k * 3 + 1] * camera->at[1]
                       + rot[k * 3 + 2] * camera->at[2];
        d[k] = (float)(o->motion[k] - moved);
    }
    const int rows[3] = {0, 1, 3};
    for (int r = 0; r < 3; ++r) {
        const float *row = m + rows[r] * 4;
        for (int k = 0; k < 3; ++k)
            p->motion_rows[r * 4 + k] = (float)(row[0] * rot[k] + row[1] * rot[3 + k] + row[2] * rot[6 + k]);
        p->motion_rows[r * 4 + 3] = row[0] * d[0] + row[1] * d[1] + row[2] * d[2];
    }
}

/* Motion blur and depth of field in clip space: the motion's clip-space
 * delta (the matrix without translation) and the lens radius in clip x
 * and y units (rows 0 and 1 scale the camera's right and up vectors).
 * Off, and the unblurred code path, when both are zero. */
static void set_blur(const reyes_camera *camera, const reyes_options *o, struct reyes_params *p)
{
    const float *m = p->view_proj, *d = o->motion;
    p->blur = d[0] != 0.0f || d[1] != 0.0f || d[2] != 0.0f || o->aperture != 0.0f
              || o->motion_angle_deg != 0.0f;
    if (!p->blur)
        return;
    p->time_samples = o->time_samples ? o->time_samples : o->spp;
    p->blur_algo = o->blur_algo;
    p->blur_tile = o->blur_tile;
    p->blur_permutations = o->blur_permutations;
    set_motion(camera, o, p);
    p->lens_x = o->aperture * sqrtf(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    p->lens_y = o->aperture * sqrtf(m[4] * m[4] + m[5] * m[5] + m[6] * m[6]);
    float target = 0.0f;
    for (int k = 0; k < 3; ++k)
        target += (camera->at[k] - camera->eye[k]) * (camera->at[k] - camera->eye[k]);
    p->focus = o->focus > 0.0f ? o->focus : sqrtf(target);
    if (!(p->focus > 0.0f))
        p->focus = 1.0f;
}

/* Shading-rate counts (reyes_rate.cl): chords within a fiftieth of a
 * pixel of the surface on screen where it bends, in pieces no shorter
 * than half the rate's side in space (docs/reyes-dicing.md: what these buy and
 * cost). */
#define REYES_RATE_SAG 0.02f
#define REYES_RATE_MIN_PIECE 0.5f

/* Sample shading: the world direction of the ray through pixel point
 * (x, y), away from the eye, is ray_origin + x ray_dx + y ray_dy.  With
 * a0, a1, a3 the xyz of the matrix rows x, y and w, the points with
 * normalised device coordinates (nx, ny) satisfy (a0 - nx a3) . d = 0
 * and (a1 - ny a3) . d = 0, so d is their cross product,
 * a0 x a1 - nx (a3 x a1) - ny (a0 x a3): affine in nx and ny, and so in
 * the pixel coordinates. */
static void set_rays(struct reyes_params *p)
{
    const float *m = p->view_proj;
    double a[3][3];
    for (int k = 0; k < 3; ++k) {
        a[0][k] = m[k];
        a[1][k] = m[4 + k];
        a[2][k] = m[12 + k];
    }
    double c01[3], c31[3], c03[3];
    for (int k = 0; k < 3; ++k) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        c01[k] = a[0][i] * a[1][j] - a[0][j] * a[1][i];
        c31[k] = a[2][i] * a[1][j] - a[2][j] * a[1][i];
        c03[k] = a[0][i] * a[2][j] - a[0][j] * a[2][i];
    }
    double forward = c01[0] * a[2][0] + c01[1] * a[2][1] + c01[2] * a[2][2];
    double sign = forward < 0.0 ? -1.0 : 1.0;
    for (int k = 0; k < 3; ++k) {
        /* nx = 2 x / width - 1, ny = 1 - 2 y / height. */
        p->ray_origin[k] = (float)(sign * (c01[k] + c31[k] - c03[k]));
        p->ray_dx[k] = (float)(sign * -2.0 / p->width * c31[k]);
        p->ray_dy[k] = (float)(sign * 2.0 / p->height * c03[k]);
    }
}

reyes_status render_fill_params(const reyes_scene *scene, const reyes_camera *camera, const reyes_options *o,
                                struct reyes_params *p, reyes_error *error)
{
    memset(p, 0, sizeof *p);
    /* Nothing closer than this is projected; patches crossing it are split. */
    p->near_w = reyes_near_plane(scene, camera);
    reyes_status status = reyes_camera_matrix(camera, (float)o->width / (float)o->height, p->near_w,
                                              p->view_proj, error);
    if (status != REYES_OK)
        return status;
    for (int k = 0; k < 3; ++k)
        p->eye[k] = camera->eye[k];
    reyes_light_direction(p->light_dir);
    p->width = (float)o->width;
    p->height = (float)o->height;
    p->bound_px = o->bound_px;
    p->subdivision = o->subdivision;
    p->flat_epsilon = o->flat_epsilon;
    p->flat_lambda = o->flat_lambda;
    p->flat_cap_px = o->flat_bound_px > 0.0f ? o->flat_bound_px : (float)(o->grid - 1u);
    p->wedges = o->crack_fix == REYES_CRACK_FIX_WEDGE ? 1u : 0u;
    p->polyline = o->crack_fix == REYES_CRACK_FIX_POLYLINE ? 1u : 0u;
    p->cull_margin = o->cull_margin;
    p->ambient = REYES_AMBIENT;
    p->diffuse = REYES_DIFFUSE;
    p->specular = REYES_SPECULAR;
    p->shininess = REYES_SHININESS;
    p->max_depth = o->max_depth;
    p->grid = o->grid;
    p->shading_rate = o->shading_rate;
    p->show_grid_sizes = o->show_grid_sizes ? 1u : 0u;
    p->spp = o->spp;
    p->backface_cull = o->backface_cull ? 1u : 0u;
    p->stages = o->stages;
    set_blur(camera, o, p);
    p->sample_shading = o->shading_rate > 0.0f && !p->blur;
    p->area_stats = o->area_stats && !p->blur && o->stages == REYES_STAGES_ALL;
    set_rays(p);
    p->rate_sag = REYES_RATE_SAG;
    p->rate_min_piece = REYES_RATE_MIN_PIECE;
    /* Like the sampleless test: fixed grids (--grid N) keep the
     * reference's counts; displaced and blurred grids leave their hull. */
    int displaced = o->displace_mode != REYES_DISPLACE_NONE && o->displace_amplitude != 0.0f;
    p->occlusion_cull = o->occlusion_cull && o->shading_rate > 0.0f && !p->blur && !p->wedges && !displaced
                        && o->stages == REYES_STAGES_ALL;
    return REYES_OK;
}
