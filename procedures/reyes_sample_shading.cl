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

/* Whether a vertex faces the eye: its normal against the ray through
 * its pixel point (any length). */
#define REYES_DEFINE_FACES_EYE(name, F, I)                                     \
    REYES_INLINE I name(__global const struct reyes_params *p, F nx, F ny, F nz, F sx, F sy) \
    {                                                                          \
        F vx = p->ray_origin[0] + sx * p->ray_dx[0] + sy * p->ray_dy[0];       \
        F vy = p->ray_origin[1] + sx * p->ray_dx[1] + sy * p->ray_dy[1];       \
        F vz = p->ray_origin[2] + sx * p->ray_dx[2] + sy * p->ray_dy[2];       \
        return nx * vx + ny * vy + nz * vz <= 0.0f;                            \
    }
REYES_DEFINE_FACES_EYE(reyes_faces_eye, float, int)
REYES_DEFINE_FACES_EYE(reyes_faces_eye16, float16, int16)

/* The colour of base colour `base` lit at a sample at pixel point
 * (sx, sy) whose interpolated normal is (nx, ny, nz) (any length; a zero
 * one faces the eye): Lambert plus Blinn-Phong, two-sided, packed as
 * reyes_light_color_lanes.  A normal facing away is turned towards the
 * eye as the look does (negated), except on a micropolygon whose corners
 * face different ways (`fold`: it spans a silhouette where the surface
 * turns away, and the sample stands for the front of the fold, whose
 * normal is nearly across the ray): there only its part along the ray is
 * turned round, so it keeps its direction across the ray. */
#define REYES_DEFINE_SAMPLE_LIGHT(name, F, U, I, power, byte)                  \
    REYES_INLINE U name(__global const struct reyes_params *p, F nx, F ny, F nz, F sx, F sy, I fold, uint base) \
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
        F along = nx * vx + ny * vy + nz * vz;                                 \
        F turn = select((F)0.0f, -2.0f * along, (along < 0.0f) & (fold != 0));   \
        F side = select((F)1.0f, (F)-1.0f, (along < 0.0f) & (fold == 0));      \
        nx = side * (nx + turn * vx);                                          \
        ny = side * (ny + turn * vy);                                          \
        nz = side * (nz + turn * vz);                                          \
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
REYES_DEFINE_SAMPLE_LIGHT(reyes_sample_light, float, uint, int, reyes_power, reyes_channel_byte)
REYES_DEFINE_SAMPLE_LIGHT(reyes_sample_light8, float8, uint8, int8, reyes_power8, reyes_channel_byte8)
REYES_DEFINE_SAMPLE_LIGHT(reyes_sample_light16, float16, uint16, int16, reyes_power_lanes, reyes_channel_byte16)
