/* Look-at perspective camera and automatic framing. */
#include <math.h>

#include "reyes.h"

#define DEG_TO_RAD 0.01745329252f

static void sub3(const float a[3], const float b[3], float out[3])
{
    for (int k = 0; k < 3; ++k)
        out[k] = a[k] - b[k];
}

static float dot3(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const float a[3], const float b[3], float out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* Normalise in place; 0 if the vector is (nearly) zero. */
static int normalize3(float v[3])
{
    float length = sqrtf(dot3(v, v));
    if (!(length > 1e-20f) || !isfinite(length))
        return 0;
    for (int k = 0; k < 3; ++k)
        v[k] /= length;
    return 1;
}

static reyes_status check_fov(float fov_deg, reyes_error *error)
{
    if (!(fov_deg > 0.5f && fov_deg < 179.0f))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "field of view %g is not in (0.5, 179) degrees",
                          (double)fov_deg);
    return REYES_OK;
}

/* Distance from the target at which every control point of the bulk is in
 * view: a point at (x, y) across the view and z along it (towards the
 * scene) needs distance + z >= |x| / tan(half_h) and >= |y| / tan(half_v). */
static float fit_distance(const reyes_scene *scene, const reyes_bulk *bulk, const float center[3],
                          const float forward[3], const float side[3], const float up[3], float tan_v,
                          float tan_h, float radius)
{
    float distance = 0.0f;
    for (size_t i = 0; i < scene->patch_count * 16; ++i) {
        if (!reyes_bulk_holds(bulk, scene->points + i * 4))
            continue;
        float d[3];
        sub3(scene->points + i * 4, center, d);
        float need = fmaxf(fabsf(dot3(d, side)) / tan_h, fabsf(dot3(d, up)) / tan_v) - dot3(d, forward);
        /* and stay in front of the points, not only around them */
        need = fmaxf(need, 0.05f * radius - dot3(d, forward));
        distance = fmaxf(distance, need);
    }
    return distance > 0.0f ? distance : radius;
}

reyes_status reyes_camera_frame(const reyes_scene *scene, float fov_deg, float aspect,
                                reyes_camera *camera, reyes_error *error)
{
    reyes_status status = check_fov(fov_deg, error);
    if (status != REYES_OK)
        return status;
    if (!(aspect > 0.0f))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "aspect ratio must be positive");
    float lo[3] = {-1, -1, -1}, hi[3] = {1, 1, 1};
    reyes_bulk bulk;
    if (reyes_scene_bulk(scene, &bulk))
        for (int k = 0; k < 3; ++k) {
            lo[k] = bulk.lo[k];
            hi[k] = bulk.hi[k];
        }
    float center[3], diagonal[3];
    for (int k = 0; k < 3; ++k) {
        center[k] = 0.5f * (lo[k] + hi[k]);
        diagonal[k] = hi[k] - lo[k];
    }
    float radius = 0.5f * sqrtf(dot3(diagonal, diagonal));
    if (!(radius > 1e-6f))
        radius = 1.0f;
    /* Look from the front, a little right and above (z up). */
    float to_eye[3] = {0.35f, -1.0f, 0.45f}, forward[3], side[3], up[3];
    const float z_axis[3] = {0.0f, 0.0f, 1.0f};
    normalize3(to_eye);
    for (int k = 0; k < 3; ++k)
        forward[k] = -to_eye[k];
    cross3(forward, z_axis, side);
    normalize3(side);
    cross3(side, forward, up);
    float tan_v = tanf(0.5f * fov_deg * DEG_TO_RAD);
    float distance = fit_distance(scene, &bulk, center, forward, side, up, tan_v, tan_v * aspect, radius);
    distance *= 1.04f; /* a small border */
    for (int k = 0; k < 3; ++k) {
        camera->at[k] = center[k];
        camera->eye[k] = center[k] + distance * to_eye[k];
    }
    camera->fov_deg = fov_deg;
    return REYES_OK;
}

reyes_status reyes_camera_matrix(const reyes_camera *camera, float aspect, float near_w,
                                 float m[16], reyes_error *error)
{
    reyes_status status = check_fov(camera->fov_deg, error);
    if (status != REYES_OK)
        return status;
    for (int k = 0; k < 6; ++k) {
        const float *point = k < 3 ? camera->eye : camera->at;
        if (!(fabsf(point[k % 3]) <= REYES_MAX_COORDINATE))
            return reyes_fail(error, REYES_ERR_ARGUMENT, "camera %s (%g, %g, %g) is beyond +-%g, the supported range "
                              "of coordinates", k < 3 ? "eye" : "target", (double)point[0], (double)point[1],
                              (double)point[2], (double)REYES_MAX_COORDINATE);
    }
    (void)near_w; /* depth is the clip w itself; the near plane is tested on w */
    float forward[3], side[3], up[3] = {0.0f, 0.0f, 1.0f}, true_up[3];
    sub3(camera->at, camera->eye, forward);
    if (!normalize3(forward))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "camera eye and target are the same point");
    cross3(forward, up, side);
    if (!normalize3(side)) {
        /* Looking straight up or down: use y as up. */
        up[1] = 1.0f;
        up[2] = 0.0f;
        cross3(forward, up, side);
        normalize3(side);
    }
    cross3(side, forward, true_up);
    float t = tanf(0.5f * camera->fov_deg * DEG_TO_RAD);
    const float *rows[4] = {side, true_up, forward, forward};
    const float scale[4] = {1.0f / (t * aspect), 1.0f / t, 1.0f, 1.0f};
    for (int r = 0; r < 4; ++r) {
        for (int k = 0; k < 3; ++k)
            m[r * 4 + k] = scale[r] * rows[r][k];
        m[r * 4 + 3] = -scale[r] * dot3(rows[r], camera->eye);
    }
    return REYES_OK;
}

int reyes_camera_project(const float m[16], unsigned width, unsigned height, const float x[3],
                         float *px, float *py, float *depth)
{
    float clip[4];
    for (int r = 0; r < 4; ++r)
        clip[r] = m[r * 4] * x[0] + m[r * 4 + 1] * x[1] + m[r * 4 + 2] * x[2] + m[r * 4 + 3];
    if (!(clip[3] > 0.0f))
        return 0;
    *px = (clip[0] / clip[3] * 0.5f + 0.5f) * (float)width;
    *py = (0.5f - clip[1] / clip[3] * 0.5f) * (float)height;
    *depth = clip[3];
    return 1;
}
