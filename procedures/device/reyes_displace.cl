/*
 * Displacement: displace(d, uv, p, n) is the distance to move the surface
 * point p (base-patch parameters uv, unit normal n) along n.  The built-in
 * kinds (reyes_params.displace_mode): procedural bumps, a smooth value
 * noise of the world position in [0, amplitude]; and a grayscale map
 * sampled bilinearly at uv (white = amplitude).  The context d holds the
 * parameters and the map.  Every input is a function of (patch, u, v), so
 * a vertex shared by two grids is displaced identically.
 */

struct reyes_displacement {
    __global const struct reyes_params *params;
    __global const uchar *map;    /* map_width x map_height gray bytes, rows top down */
};

/* Hash of an integer lattice point to [0,1). */
float reyes_lattice_value(int3 c)
{
    uint h = (uint)c.x * 0x8da6b343u ^ (uint)c.y * 0xd8163841u ^ (uint)c.z * 0xcb1ab31fu;
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    return (float)(h >> 8) * (1.0f / 16777216.0f);
}

/* Value noise in [0,1]: trilinear interpolation of lattice values with a
 * smoothstep weight (continuous, with a continuous gradient). */
float reyes_value_noise(float3 x)
{
    float3 cell = floor(x);
    float3 f = x - cell;
    float3 w = f * f * (3.0f - 2.0f * f);
    int3 c = convert_int3(cell);
    float v[8];
    for (int k = 0; k < 8; ++k)
        v[k] = reyes_lattice_value(c + (int3)(k & 1, (k >> 1) & 1, k >> 2));
    float x00 = mix(v[0], v[1], w.x), x10 = mix(v[2], v[3], w.x);
    float x01 = mix(v[4], v[5], w.x), x11 = mix(v[6], v[7], w.x);
    return mix(mix(x00, x10, w.y), mix(x01, x11, w.y), w.z);
}

/* Gray value of the map at uv in [0,1]^2, bilinear, clamped at the border. */
float reyes_map_value(const struct reyes_displacement *d, float2 uv)
{
    __global const struct reyes_params *p = d->params;
    int w = (int)p->map_width, h = (int)p->map_height;
    float x = clamp(uv.x, 0.0f, 1.0f) * (float)(w - 1);
    float y = clamp(uv.y, 0.0f, 1.0f) * (float)(h - 1);
    int x0 = min((int)x, w - 1), y0 = min((int)y, h - 1);
    int x1 = min(x0 + 1, w - 1), y1 = min(y0 + 1, h - 1);
    float fx = x - (float)x0, fy = y - (float)y0;
    float a = (float)d->map[y0 * w + x0], b = (float)d->map[y0 * w + x1];
    float c = (float)d->map[y1 * w + x0], e = (float)d->map[y1 * w + x1];
    return mix(mix(a, b, fx), mix(c, e, fx), fy) * (1.0f / 255.0f);
}

float displace(const struct reyes_displacement *d, float2 uv, float3 p, float3 n)
{
    (void)n;
    __global const struct reyes_params *params = d->params;
    if (params->displace_mode == REYES_DISPLACE_BUMPS)
        return params->displace_amplitude * reyes_value_noise(p * params->displace_frequency);
    if (params->displace_mode == REYES_DISPLACE_MAP)
        return params->displace_amplitude * reyes_map_value(d, uv);
    return 0.0f;
}
