/*
 * Sample shading (reyes_params.sample_shading: a shading rate without
 * blur).  dice stores each vertex's unit normal, packed, where fixed
 * grids store its colour, and rasterize and stitch light every covered
 * sample: the normal interpolated from its triangle's vertices, seen
 * along the sample's own ray, with the light, weights and two-sidedness
 * of reyes_light_lanes (reyes_surface.cl).  With micropolygons of about a
 * pixel, colours interpolated from their corners flatten and dim every
 * highlight narrower than a few of them and shift shading across
 * creases; a normal interpolated over a pixel is within a fraction of a
 * degree of the surface's.  Each function is defined for one lane and for
 * the 8 and 16 lanes of rasterize.
 */

/* x^s: by squaring for a whole exponent up to 64 (the look's is 40: six
 * products, as the C reference), else exp2(s log2 x) at native precision
 * (pow() is PoCL's full-precision library call and took about a fifth of
 * a teapot render; native_log2 looks a table up lane by lane). */
#define REYES_DEFINE_POWER(name, F)                                            \
    REYES_INLINE F name(F x, float s)                                          \
    {                                                                          \
        uint n = (uint)s;                                                      \
        if (s >= 0.0f && s <= 64.0f && (float)n == s) {                       \
            F result = (F)1.0f, base = x;                                      \
            for (; n != 0u; n >>= 1) {                                         \
                if (n & 1u)                                                    \
                    result *= base;                                            \
                base *= base;                                                  \
            }                                                                  \
            return result;                                                     \
        }                                                                      \
        return native_exp2(s * native_log2(x));                                \
    }
REYES_DEFINE_POWER(reyes_power, float)
REYES_DEFINE_POWER(reyes_power8, float8)
REYES_DEFINE_POWER(reyes_power_lanes, float16)

/* A unit normal as two 16-bit octahedral coordinates (x in the low
 * half): its point on the octahedron |x| + |y| + |z| = 1 seen from above,
 * the lower half folded over the upper: within a twentieth of a degree
 * of the normal.  A zero vector packs as +z. */
REYES_INLINE uint16 reyes_pack_normal16(float16 x, float16 y, float16 z)
{
    float16 sum = fabs(x) + fabs(y) + fabs(z);
    int16 zero = sum == 0.0f;
    float16 inv = select(1.0f / sum, (float16)0.0f, zero);
    float16 px = x * inv, py = y * inv;
    int16 lower = z < 0.0f;
    float16 fx = select(px, (1.0f - fabs(py)) * copysign((float16)1.0f, px), lower);
    float16 fy = select(py, (1.0f - fabs(px)) * copysign((float16)1.0f, py), lower);
    uint16 ux = convert_uint16_sat_rte((fx * 0.5f + 0.5f) * 65535.0f);
    uint16 uy = convert_uint16_sat_rte((fy * 0.5f + 0.5f) * 65535.0f);
    return ux | (uy << 16);
}

/* The unit normal of a packed one. */
#define REYES_DEFINE_UNPACK_NORMAL(name, F, U, convert)                        \
    REYES_INLINE void name(U code, F *x, F *y, F *z)                           \
    {                                                                          \
        F fx = convert(code & 0xffffu) * (2.0f / 65535.0f) - 1.0f;             \
        F fy = convert(code >> 16) * (2.0f / 65535.0f) - 1.0f;                 \
        F fz = 1.0f - fabs(fx) - fabs(fy);                                     \
        F fold = fmax(-fz, 0.0f);                                              \
        fx -= copysign(fold, fx);                                              \
        fy -= copysign(fold, fy);                                              \
        F inv = rsqrt(fx * fx + fy * fy + fz * fz);                            \
        *x = fx * inv;                                                         \
        *y = fy * inv;                                                         \
        *z = fz * inv;                                                         \
    }
REYES_DEFINE_UNPACK_NORMAL(reyes_unpack_normal, float, uint, convert_float)
REYES_DEFINE_UNPACK_NORMAL(reyes_unpack_normal16, float16, uint16, convert_float16)

/* REYES_SHADE_SURFACE: a vertex's parameters in its grid's sub-patch,
 * s and t in [0,1], 16 bits each (s in the low half), packed into one
 * word. */
REYES_INLINE uint16 reyes_pack_surface16(float16 s, float16 t)
{
    uint16 us = convert_uint16_sat_rte(clamp(s, 0.0f, 1.0f) * 65535.0f);
    uint16 ut = convert_uint16_sat_rte(clamp(t, 0.0f, 1.0f) * 65535.0f);
    return us | (ut << 16);
}

#define REYES_DEFINE_UNPACK_SURFACE(name, F, U, convert)                       \
    REYES_INLINE void name(U code, F *s, F *t)                                 \
    {                                                                          \
        *s = convert(code & 0xffffu) * (1.0f / 65535.0f);                      \
        *t = convert(code >> 16) * (1.0f / 65535.0f);                          \
    }
REYES_DEFINE_UNPACK_SURFACE(reyes_unpack_surface, float, uint, convert_float)
REYES_DEFINE_UNPACK_SURFACE(reyes_unpack_surface16, float16, uint16, convert_float16)

/* A base patch's derivative nets: the differences of its control points
 * along u (4 rows of 3) and along v (3 rows of 4), x y z each. */
struct reyes_derivative_net {
    float du[4][3][3];
    float dv[3][4][3];
};

REYES_INLINE void reyes_derivative_net_of(__global const float4 *patches, uint patch, struct reyes_derivative_net *d)
{
    __global const float *f = (__global const float *)(patches + patch * 16u);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 3; ++k) {
                float here = f[(r * 4 + c) * 4 + k];
                if (c < 3)
                    d->du[r][c][k] = f[(r * 4 + c + 1) * 4 + k] - here;
                if (r < 3)
                    d->dv[r][c][k] = f[((r + 1) * 4 + c) * 4 + k] - here;
            }
}

/* The patch's normal at (u, v): the cross product of its derivatives
 * along u and v (each a third of the patch's), from the derivative net
 * with quadratic weights across the differences and cubic ones along
 * them; unnormalised. */
#define REYES_DEFINE_NET_NORMAL(name, F)                                       \
    REYES_INLINE void name(const struct reyes_derivative_net *d, F u, F v, F n[3]) \
    {                                                                          \
        F su = 1.0f - u, sv = 1.0f - v;                                        \
        F cu[4] = {su * su * su, 3.0f * u * su * su, 3.0f * u * u * su, u * u * u}; \
        F cv[4] = {sv * sv * sv, 3.0f * v * sv * sv, 3.0f * v * v * sv, v * v * v}; \
        F qu[3] = {su * su, 2.0f * u * su, u * u};                             \
        F qv[3] = {sv * sv, 2.0f * v * sv, v * v};                             \
        F tu[3] = {0.0f, 0.0f, 0.0f}, tv[3] = {0.0f, 0.0f, 0.0f};              \
        for (int r = 0; r < 4; ++r)                                            \
            for (int k = 0; k < 3; ++k)                                        \
                tu[k] += cv[r] * (qu[0] * d->du[r][0][k] + qu[1] * d->du[r][1][k] + qu[2] * d->du[r][2][k]); \
        for (int r = 0; r < 3; ++r)                                            \
            for (int k = 0; k < 3; ++k)                                        \
                tv[k] += qv[r] * (cu[0] * d->dv[r][0][k] + cu[1] * d->dv[r][1][k] + cu[2] * d->dv[r][2][k] \
                                  + cu[3] * d->dv[r][3][k]);                   \
        n[0] = tu[1] * tv[2] - tu[2] * tv[1];                                  \
        n[1] = tu[2] * tv[0] - tu[0] * tv[2];                                  \
        n[2] = tu[0] * tv[1] - tu[1] * tv[0];                                  \
    }
REYES_DEFINE_NET_NORMAL(reyes_net_normal, float)
REYES_DEFINE_NET_NORMAL(reyes_net_normal8, float8)
REYES_DEFINE_NET_NORMAL(reyes_net_normal16, float16)

/* The colour of base colour `base` lit at a sample at pixel point
 * (sx, sy) whose normal is (nx, ny, nz) (any length; a zero one faces
 * the eye): Lambert plus Blinn-Phong, two-sided (a normal facing away is
 * negated, as reyes_light_lanes does), packed as
 * reyes_light_color_lanes. */
#define REYES_DEFINE_SAMPLE_LIGHT(name, F, U, power, byte)                     \
    REYES_INLINE U name(__global const struct reyes_params *p, F nx, F ny, F nz, F sx, F sy, uint base) \
    {                                                                          \
        F vx = -(p->ray_origin[0] + sx * p->ray_dx[0] + sy * p->ray_dy[0]);    \
        F vy = -(p->ray_origin[1] + sx * p->ray_dx[1] + sy * p->ray_dy[1]);    \
        F vz = -(p->ray_origin[2] + sx * p->ray_dx[2] + sy * p->ray_dy[2]);    \
        F inv_v = rsqrt(vx * vx + vy * vy + vz * vz);                          \
        vx *= inv_v;                                                           \
        vy *= inv_v;                                                           \
        vz *= inv_v;                                                           \
        F n2 = nx * nx + ny * ny + nz * nz;                                    \
        F inv_n = rsqrt(n2);                                                   \
        nx = select(vx, nx * inv_n, n2 > 0.0f);                                \
        ny = select(vy, ny * inv_n, n2 > 0.0f);                                \
        nz = select(vz, nz * inv_n, n2 > 0.0f);                                \
        F side = select((F)1.0f, (F)-1.0f, nx * vx + ny * vy + nz * vz < 0.0f); \
        nx *= side;                                                            \
        ny *= side;                                                            \
        nz *= side;                                                            \
        float lx = p->light_dir[0], ly = p->light_dir[1], lz = p->light_dir[2]; \
        F lambert = fmax(nx * lx + ny * ly + nz * lz, 0.0f);                   \
        F hx = lx + vx, hy = ly + vy, hz = lz + vz;                            \
        F cos_h = (nx * hx + ny * hy + nz * hz) * rsqrt(hx * hx + hy * hy + hz * hz); \
        F highlight = select((F)0.0f, power(cos_h, p->shininess), (lambert > 0.0f) & (cos_h > 0.0f)); \
        F diffuse = p->ambient + p->diffuse * lambert;                         \
        F specular = p->specular * highlight;                                  \
        float r = reyes_channel(base, 0u), g = reyes_channel(base, 8u), b = reyes_channel(base, 16u); \
        return byte(r * diffuse + specular) | (byte(g * diffuse + specular) << 8) \
               | (byte(b * diffuse + specular) << 16) | (U)(255u << 24);      \
    }
REYES_DEFINE_SAMPLE_LIGHT(reyes_sample_light, float, uint, reyes_power, reyes_channel_byte)
REYES_DEFINE_SAMPLE_LIGHT(reyes_sample_light8, float8, uint8, reyes_power8, reyes_channel_byte8)
REYES_DEFINE_SAMPLE_LIGHT(reyes_sample_light16, float16, uint16, reyes_power_lanes, reyes_channel_byte16)
