/*
 * Motion blur and depth of field with the simple UVT algorithm: every
 * sample of a pixel has its own time t (stratified over time_samples) and
 * lens position (uniform on the disk); a micropolygon is tested against
 * each sample in the screen box it can cover over the shutter and the
 * lens, with its vertices moved to that sample's t and lens position.
 * Time and lens depend on the global pixel and sample index only, so the
 * image does not depend on the schedule.
 */

/* A hashed number in [0,1) for (pixel, sample, dimension). */
float reyes_sample_dimension(uint px, uint py, uint s, uint dimension)
{
    uint h = reyes_hash(px * 0x9e3779b9u ^ reyes_hash(py * 0x85ebca6bu
                        ^ reyes_hash(s * 0xc2b2ae35u ^ reyes_hash(dimension + 0x27d4eb2fu))));
    return (float)(h >> 8) * (1.0f / 16777216.0f);
}

/* Time of a sample: stratum s mod strata, jittered. */
float reyes_sample_time(uint px, uint py, uint s, uint strata)
{
    return ((float)(s % strata) + reyes_sample_dimension(px, py, s, 1u)) / (float)strata;
}

/* Lens position on the unit disk (concentric mapping of the square). */
float2 reyes_sample_lens(uint px, uint py, uint s)
{
    float a = 2.0f * reyes_sample_dimension(px, py, s, 2u) - 1.0f;
    float b = 2.0f * reyes_sample_dimension(px, py, s, 3u) - 1.0f;
    if (a == 0.0f && b == 0.0f)
        return (float2)(0.0f, 0.0f);
    float r, phi;
    if (fabs(a) > fabs(b)) {
        r = a;
        phi = (M_PI_F / 4.0f) * (b / a);
    } else {
        r = b;
        phi = (M_PI_F / 2.0f) - (M_PI_F / 4.0f) * (a / b);
    }
    return (float2)(r * cos(phi), r * sin(phi));
}

/* Clip position of a vertex (clip x, y, w) at time t and lens position. */
float3 reyes_blur_clip(__global const struct reyes_params *p, float x, float y, float w, float t,
                       float2 lens)
{
    float wt = w + t * p->motion_w;
    float defocus = wt / p->focus - 1.0f;
    return (float3)(x + t * p->motion_x + defocus * lens.x * p->lens_x,
                    y + t * p->motion_y + defocus * lens.y * p->lens_y, wt);
}

/* Screen box of a blurred quad: its vertices at t = 0 and 1 and the four
 * corners of the lens square (offsets are linear in t and in the lens
 * position).  0 if a vertex can reach the near plane (then the tile). */
int reyes_blur_box(__global const struct reyes_params *p, const struct reyes_quad *q, int corners,
                   float2 *lo, float2 *hi)
{
    *lo = (float2)(INFINITY, INFINITY);
    *hi = (float2)(-INFINITY, -INFINITY);
    for (int k = 0; k < corners; ++k) {
        for (int c = 0; c < 8; ++c) {
            float t = (float)(c & 1);
            float2 lens = (float2)((c & 2) ? 1.0f : -1.0f, (c & 4) ? 1.0f : -1.0f);
            float3 clip = reyes_blur_clip(p, q->x[k], q->y[k], q->z[k], t, lens);
            if (clip.z <= p->near_w)
                return 0;
            float2 s = reyes_to_screen(p, (float4)(clip.x, clip.y, 0.0f, clip.z));
            *lo = fmin(*lo, s);
            *hi = fmax(*hi, s);
        }
    }
    return 1;
}

/* Test every sample in the quad's blurred box (clipped to the tile). */
void reyes_rasterize_blurred(__global const struct reyes_params *p, __global ulong *samples,
                             const struct reyes_quad *q, int triangles)
{
    float2 lo, hi;
    if (!reyes_blur_box(p, q, triangles == 2 ? 4 : 3, &lo, &hi)) {
        lo = (float2)(p->tile_x0, p->tile_y0);
        hi = (float2)(p->tile_x1, p->tile_y1);
    }
    if (hi.x < p->tile_x0 || hi.y < p->tile_y0 || lo.x > p->tile_x1 || lo.y > p->tile_y1)
        return;
    int x0 = (int)floor(clamp(lo.x, p->tile_x0, p->tile_x1 - 1.0f));
    int x1 = (int)floor(clamp(hi.x, p->tile_x0, p->tile_x1 - 1.0f));
    int y0 = (int)floor(clamp(lo.y, p->tile_y0, p->tile_y1 - 1.0f));
    int y1 = (int)floor(clamp(hi.y, p->tile_y0, p->tile_y1 - 1.0f));
    uint tile_x = (uint)p->tile_x0, tile_y = (uint)p->tile_y0;
    uint tile_width = (uint)p->tile_x1 - tile_x, spp = p->spp;
    for (int py = y0; py <= y1; ++py) {
        for (int px = x0; px <= x1; ++px) {
            for (uint s = 0; s < spp; ++s) {
                float t = reyes_sample_time((uint)px, (uint)py, s, p->time_samples);
                float2 lens = reyes_sample_lens((uint)px, (uint)py, s);
                struct reyes_quad moved = *q;
                int in_front = 1;
                for (int k = 0; k < 4; ++k) {
                    float3 clip = reyes_blur_clip(p, q->x[k], q->y[k], q->z[k], t, lens);
                    in_front &= clip.z > p->near_w;
                    float2 sc = reyes_to_screen(p, (float4)(clip.x, clip.y, 0.0f, fmax(clip.z, p->near_w)));
                    moved.x[k] = sc.x;
                    moved.y[k] = sc.y;
                    moved.z[k] = clip.z;
                }
                if (!in_front)
                    continue;
                float2 pos = reyes_sample_position((uint)px, (uint)py, s, spp);
                uint index = (((uint)py - tile_y) * tile_width + ((uint)px - tile_x)) * spp + s;
                reyes_sample_triangle(samples, index, pos, &moved, 0, 1, 2);
                if (triangles == 2)
                    reyes_sample_triangle(samples, index, pos, &moved, 0, 2, 3);
            }
        }
    }
}
