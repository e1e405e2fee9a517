/*
 * The built-in scene, generated in code: spheres and a torus as surfaces of
 * revolution (a cubic profile swept by cubic quarter circles) and a wavy
 * ribbon.  z is up.
 */
#include <math.h>

#include "reyes.h"

/* Control-point offset of the cubic Bézier quarter circle. */
#define QUARTER_K 0.5522847498f

/* Cubic Bézier approximation of the unit circle arc from quarter * 90
 * degrees to (quarter + 1) * 90 degrees: out[k] = (cos, sin) like control
 * point k.  The end points are exact (0 or +-1), so neighbouring arcs share
 * them bit for bit and the swept surfaces close without a seam. */
static void quarter_arc(int quarter, float out[4][2])
{
    static const float cosines[4] = {1.0f, 0.0f, -1.0f, 0.0f};
    int qa = ((quarter % 4) + 4) % 4, qb = (qa + 1) % 4;
    float ca = cosines[qa], sa = cosines[(qa + 3) % 4], cb = cosines[qb], sb = cosines[(qb + 3) % 4];
    out[0][0] = ca;
    out[0][1] = sa;
    out[1][0] = ca - QUARTER_K * sa;
    out[1][1] = sa + QUARTER_K * ca;
    out[2][0] = cb + QUARTER_K * sb;
    out[2][1] = sb - QUARTER_K * cb;
    out[3][0] = cb;
    out[3][1] = sb;
}

/* Sweep a profile (radius, height) around the z axis through center:
 * rows follow the profile (v), columns the circle (u); 4 patches. */
static reyes_status add_revolution(reyes_scene *scene, const float center[3],
                                   const float profile[4][2], uint32_t rgba, reyes_error *error)
{
    for (int quarter = 0; quarter < 4; ++quarter) {
        float arc[4][2];
        quarter_arc(quarter, arc);
        float cp[4][4][3];
        for (int r = 0; r < 4; ++r) {
            for (int c = 0; c < 4; ++c) {
                cp[r][c][0] = center[0] + profile[r][0] * arc[c][0];
                cp[r][c][1] = center[1] + profile[r][0] * arc[c][1];
                cp[r][c][2] = center[2] + profile[r][1];
            }
        }
        reyes_status status = reyes_scene_add_patch(scene, cp, rgba, error);
        if (status != REYES_OK)
            return status;
    }
    return REYES_OK;
}

reyes_status reyes_scene_add_sphere(reyes_scene *scene, const float center[3], float radius,
                                    uint32_t rgba, reyes_error *error)
{
    if (!(radius > 0.0f))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "sphere radius must be positive");
    /* Two quarter meridians, from the south pole up to the equator and on
     * to the north pole. */
    for (int half = 0; half < 2; ++half) {
        float arc[4][2], profile[4][2];
        quarter_arc(half - 1, arc);
        for (int k = 0; k < 4; ++k) {
            profile[k][0] = radius * arc[k][0];
            profile[k][1] = radius * arc[k][1];
        }
        /* The poles lie exactly on the axis. */
        profile[half == 0 ? 0 : 3][0] = 0.0f;
        reyes_status status = add_revolution(scene, center, profile, rgba, error);
        if (status != REYES_OK)
            return status;
    }
    return REYES_OK;
}

reyes_status reyes_scene_add_torus(reyes_scene *scene, const float center[3], float major,
                                   float minor, uint32_t rgba, reyes_error *error)
{
    if (!(minor > 0.0f) || !(major > minor))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "torus needs 0 < minor radius < major radius");
    for (int quarter = 0; quarter < 4; ++quarter) {
        float arc[4][2], profile[4][2];
        quarter_arc(quarter, arc);
        for (int k = 0; k < 4; ++k) {
            profile[k][0] = major + minor * arc[k][0];
            profile[k][1] = minor * arc[k][1];
        }
        reyes_status status = add_revolution(scene, center, profile, rgba, error);
        if (status != REYES_OK)
            return status;
    }
    return REYES_OK;
}

reyes_status reyes_scene_add_ribbon(reyes_scene *scene, const float start[3], float length,
                                    float width, int pieces, uint32_t rgba, reyes_error *error)
{
    if (pieces < 1 || !(length > 0.0f) || !(width > 0.0f))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "ribbon needs positive size and pieces");
    float piece = length / (float)pieces;
    float amplitude = 0.6f * piece;
    /* Each piece is a half wave; alternating signs keep the joins smooth
     * (the end tangent of one piece equals the start tangent of the next). */
    static const float bump[4] = {0.0f, 1.0f, 1.0f, 0.0f};
    for (int p = 0; p < pieces; ++p) {
        float sign = (p % 2) ? -1.0f : 1.0f;
        float cp[4][4][3];
        for (int r = 0; r < 4; ++r) {
            float across = width * ((float)r / 3.0f - 0.5f);
            for (int c = 0; c < 4; ++c) {
                float x = piece * ((float)p + (float)c / 3.0f);
                cp[r][c][0] = start[0] + x;
                cp[r][c][1] = start[1] + across;
                /* A gentle twist: the wave is taller on one edge. */
                cp[r][c][2] = start[2] + sign * amplitude * bump[c] * (1.0f + across / width);
            }
        }
        reyes_status status = reyes_scene_add_patch(scene, cp, rgba, error);
        if (status != REYES_OK)
            return status;
    }
    return REYES_OK;
}

reyes_status reyes_scene_add_builtin(reyes_scene *scene, reyes_error *error)
{
    const float big[3] = {-1.4f, 0.3f, 1.0f}, small[3] = {1.3f, 0.9f, 0.7f};
    const float ring[3] = {0.5f, -1.3f, 0.3f}, ribbon[3] = {-3.0f, 2.2f, 1.9f};
    reyes_status status = reyes_scene_add_sphere(scene, big, 1.0f, REYES_RGBA(200, 70, 60), error);
    if (status == REYES_OK)
        status = reyes_scene_add_sphere(scene, small, 0.7f, REYES_RGBA(70, 130, 200), error);
    if (status == REYES_OK)
        status = reyes_scene_add_torus(scene, ring, 0.9f, 0.3f, REYES_RGBA(220, 190, 60), error);
    if (status == REYES_OK)
        status = reyes_scene_add_ribbon(scene, ribbon, 6.0f, 1.2f, 6, REYES_RGBA(90, 170, 90), error);
    return status;
}
