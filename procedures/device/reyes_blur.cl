/*
 * Motion blur and depth of field: every sample has a time t in [0,1) and
 * a lens position on the unit disk, taken from a pool of such (u,v,t)
 * tuples.  Three algorithms (Fatahalian et al. 2009; Sattlecker and
 * Steinberger 2015) differ in which tuple a sample uses and in how a
 * micropolygon finds the samples it covers (N = spp):
 *
 * simple       sample s of every pixel uses tuple s.  One pass per tuple:
 *              move the quad to that time and lens position and test
 *              sample s of the pixels in the moved quad's (small) box.
 * interleaved  pixel slot j = (py mod K) * K + (px mod K) of its K x K
 *              tile uses tuples perm(j) * N + s of a pool of K*K*N, perm
 *              one of P permutations picked by a hash of the tile.  One
 *              pass per tuple of the pool, testing in the moved box only
 *              the pixel of each tile whose slot maps to that tuple.
 * bbox         pixel (px, py) uses tuples ((py mod 64) * 64 + px mod 64)
 *              * N + s; every sample of every pixel in the box the quad
 *              sweeps over the shutter and the lens is tested with the
 *              quad moved to that sample's own tuple.
 *
 * The host makes the pool (reyes_blur_tuples.c): tuple i's time lies in
 * stratum (i mod N) mod time_samples, so each pixel's N samples are
 * stratified in time under every algorithm.  Tuples, slots and
 * permutations are functions of global pixel and sample indices only, so
 * the image does not depend on the schedule.  A sample is tested exactly
 * as without blur (reyes_sample_triangle), at the same position inside
 * its pixel.
 */

/* What the passes read and write: parameters, the tuple pool (time, lens
 * x, lens y, unused) and the tile's samples. */
struct reyes_blur {
    __global const struct reyes_params *p;
    __global const float4 *tuples;
    __global ulong *samples;
};

/* A blurred quad whose vertices all move by the parameters' one motion
 * (renderers without per-vertex motion: translation only). */
struct reyes_moving_quad reyes_moving_uniform(__global const struct reyes_params *p,
                                              const struct reyes_quad *q)
{
    struct reyes_moving_quad m;
    m.quad = *q;
    for (int k = 0; k < 4; ++k) {
        m.mx[k] = p->motion_rows[3];
        m.my[k] = p->motion_rows[7];
        m.mw[k] = p->motion_rows[11];
    }
    return m;
}

/* Clip position of vertex k (clip x, y, w plus its own motion times t) at
 * time t and lens position.  (A product with 1/focus rather than a
 * quotient: the reciprocal is hoisted out of the callers' loops.) */
float3 reyes_blur_clip(__global const struct reyes_params *p, const struct reyes_moving_quad *q, int k,
                       float t, float2 lens)
{
    float wt = q->quad.z[k] + t * q->mw[k];
    float defocus = wt * (1.0f / p->focus) - 1.0f;
    return (float3)(q->quad.x[k] + t * q->mx[k] + defocus * lens.x * p->lens_x,
                    q->quad.y[k] + t * q->my[k] + defocus * lens.y * p->lens_y, wt);
}

/* The quad (clip x, y, w) moved to tuple `index`, in pixels with z the
 * clip w, and its screen box.  0 if a vertex is at or behind the near
 * plane (the tuple's samples then see nothing of this quad). */
int reyes_blur_move(const struct reyes_blur *b, const struct reyes_moving_quad *q, uint index,
                    struct reyes_quad *moved, float2 *lo, float2 *hi)
{
    __global const struct reyes_params *p = b->p;
    float4 tuple = b->tuples[index];
    float t = tuple.x;
    float2 lens = tuple.yz;
    *moved = q->quad;
    *lo = (float2)(INFINITY, INFINITY);
    *hi = (float2)(-INFINITY, -INFINITY);
    for (int k = 0; k < 4; ++k) {
        float3 clip = reyes_blur_clip(p, q, k, t, lens);
        if (clip.z <= p->near_w)
            return 0;
        float2 sc = reyes_to_screen(p, (float4)(clip.x, clip.y, 0.0f, clip.z));
        moved->x[k] = sc.x;
        moved->y[k] = sc.y;
        moved->z[k] = clip.z;
        *lo = fmin(*lo, sc);
        *hi = fmax(*hi, sc);
    }
    return 1;
}

/* Screen box of a blurred quad over the whole shutter and lens: its
 * vertices at t = 0 and 1 and the four corners of the lens square
 * (offsets are linear in t and in the lens position).  0 if a vertex can
 * reach the near plane (then the tile). */
int reyes_blur_box(__global const struct reyes_params *p, const struct reyes_moving_quad *q, int corners,
                   float2 *lo, float2 *hi)
{
    *lo = (float2)(INFINITY, INFINITY);
    *hi = (float2)(-INFINITY, -INFINITY);
    for (int k = 0; k < corners; ++k) {
        for (int c = 0; c < 8; ++c) {
            float t = (float)(c & 1);
            float2 lens = (float2)((c & 2) ? 1.0f : -1.0f, (c & 4) ? 1.0f : -1.0f);
            float3 clip = reyes_blur_clip(p, q, k, t, lens);
            if (clip.z <= p->near_w)
                return 0;
            float2 s = reyes_to_screen(p, (float4)(clip.x, clip.y, 0.0f, clip.z));
            *lo = fmin(*lo, s);
            *hi = fmax(*hi, s);
        }
    }
    return 1;
}

/* 0 if a blurred quad's box over the shutter and lens, widened by a pixel
 * against rounding (the moved boxes lie inside it), misses the tile:
 * none of its samples there can be covered.  1 if it may reach the near
 * plane (rasterize then decides per tuple). */
int reyes_blur_meets_tile(__global const struct reyes_params *p, const struct reyes_moving_quad *q)
{
    float2 lo, hi;
    if (!reyes_blur_box(p, q, 4, &lo, &hi))
        return 1;
    return hi.x + 1.0f >= p->tile_x0 && hi.y + 1.0f >= p->tile_y0 && lo.x - 1.0f <= p->tile_x1
           && lo.y - 1.0f <= p->tile_y1;
}

/* Test sample s of global pixel (px, py) against the moved quad's
 * triangles (one for a stitch triangle, two for a quad). */
void reyes_blur_sample(const struct reyes_blur *b, const struct reyes_quad *moved, int triangles,
                       uint px, uint py, uint s)
{
    __global const struct reyes_params *p = b->p;
    __global ulong *samples = b->samples;
    uint tile_x = (uint)p->tile_x0, tile_y = (uint)p->tile_y0;
    uint tile_width = (uint)p->tile_x1 - tile_x, spp = p->spp;
    float2 pos = reyes_sample_position(px, py, s, spp);
    uint index = ((py - tile_y) * tile_width + (px - tile_x)) * spp + s;
    reyes_sample_triangle(samples, index, pos, moved, 0, 1, 2);
    if (triangles == 2)
        reyes_sample_triangle(samples, index, pos, moved, 0, 2, 3);
}

/* simple: one pass per sample index s with tuple s, the same in every
 * pixel (cheap, but every pixel sees the same N copies of the quad). */
void reyes_blur_simple(const struct reyes_blur *b, const struct reyes_moving_quad *q, int triangles)
{
    for (uint s = 0; s < b->p->spp; ++s) {
        struct reyes_quad moved;
        float2 lo, hi;
        int4 r;
        if (!reyes_blur_move(b, q, s, &moved, &lo, &hi) || !reyes_tile_pixels(b->p, lo, hi, &r))
            continue;
        for (int py = r.y; py <= r.w; ++py)
            for (int px = r.x; px <= r.z; ++px)
                reyes_blur_sample(b, &moved, triangles, (uint)px, (uint)py, s);
    }
}

/* Permutation (0..count-1) of the slots of tile (tx, ty). */
uint reyes_tile_permutation(uint tx, uint ty, uint count)
{
    return reyes_hash(tx * 0x9e3779b9u ^ reyes_hash(ty ^ 0x7f4a7c15u)) % count;
}

/* The slot of a k x k tile that permutation m maps to tuple block b: the
 * inverse of perm_m.  perm_0 is the identity; perm_m (m > 0) maps slot
 * (x, y) by three shears mod k with hashed offsets and slopes,
 *   x1 = x + a,  y1 = y + b + c x1,  x2 = x1 + d + e y1  ->  block (x2, y1),
 * each a bijection of the tile, so every block has exactly one slot. */
uint reyes_slot_of_block(uint m, uint b, uint k)
{
    if (m == 0u)
        return b;
    uint h = reyes_hash(m * 0x85ebca6bu + 0x165667b1u);
    uint a = (h & 255u) % k, bb = ((h >> 8) & 255u) % k, c = ((h >> 16) & 255u) % k;
    uint d = (h >> 24) % k, e = reyes_hash(h) % k;
    uint y1 = b / k, x2 = b % k;
    uint x1 = (x2 + k - (d + e * y1) % k) % k;
    uint y = (y1 + k - (bb + c * x1) % k) % k;
    uint x = (x1 + k - a) % k;
    return y * k + x;
}

/* The pixel of tile (tx, ty) that uses tuple block `block`. */
uint2 reyes_block_pixel(__global const struct reyes_params *p, uint tx, uint ty, uint block)
{
    uint k = p->blur_tile;
    uint slot = reyes_slot_of_block(reyes_tile_permutation(tx, ty, p->blur_permutations), block, k);
    return (uint2)(tx * k + slot % k, ty * k + slot / k);
}

int reyes_pixel_in(uint2 pixel, int4 r)
{
    return pixel.x >= (uint)r.x && pixel.x <= (uint)r.z && pixel.y >= (uint)r.y && pixel.y <= (uint)r.w;
}

/* One interleaved pass, tuple block * N + s: in the moved box, each
 * tile's pixel whose slot uses the block tests sample s. */
void reyes_blur_interleaved_pass(const struct reyes_blur *b, const struct reyes_moving_quad *q, int triangles,
                                 uint block, uint s)
{
    uint k = b->p->blur_tile;
    struct reyes_quad moved;
    float2 lo, hi;
    int4 r;
    if (!reyes_blur_move(b, q, block * b->p->spp + s, &moved, &lo, &hi)
        || !reyes_tile_pixels(b->p, lo, hi, &r))
        return;
    for (uint ty = (uint)r.y / k; ty <= (uint)r.w / k; ++ty) {
        for (uint tx = (uint)r.x / k; tx <= (uint)r.z / k; ++tx) {
            uint2 pixel = reyes_block_pixel(b->p, tx, ty, block);
            if (reyes_pixel_in(pixel, r))
                reyes_blur_sample(b, &moved, triangles, pixel.x, pixel.y, s);
        }
    }
}

/* 1 if a pixel in r (x0, y0, x1, y1) uses tuple block `block`. */
int reyes_block_used(__global const struct reyes_params *p, uint block, int4 r)
{
    uint k = p->blur_tile;
    for (uint ty = (uint)r.y / k; ty <= (uint)r.w / k; ++ty)
        for (uint tx = (uint)r.x / k; tx <= (uint)r.z / k; ++tx)
            if (reyes_pixel_in(reyes_block_pixel(p, tx, ty, block), r))
                return 1;
    return 0;
}

/* Swept boxes touching at most this many tiles take the cached path. */
#define REYES_BLUR_CACHED_TILES 16

/* The same passes over a swept box (pixels x0, y0, x1, y1) of at most
 * REYES_BLUR_CACHED_TILES tiles: each tile's permutation is hashed once,
 * and each block's pixels in the box are found once for its N passes
 * instead of in every pass.  A pixel of the block is tested in a pass
 * exactly when the moved box holds it, as in the pass above (the moved
 * box lies inside the swept one). */
void reyes_blur_interleaved_cached(const struct reyes_blur *b, const struct reyes_moving_quad *q,
                                   int triangles, int4 swept)
{
    __global const struct reyes_params *p = b->p;
    uint k = p->blur_tile, n = p->spp;
    uint tx0 = (uint)swept.x / k, ty0 = (uint)swept.y / k;
    uint columns = (uint)swept.z / k - tx0 + 1u, tiles = columns * ((uint)swept.w / k - ty0 + 1u);
    uint perm[REYES_BLUR_CACHED_TILES];
    for (uint i = 0; i < tiles; ++i)
        perm[i] = reyes_tile_permutation(tx0 + i % columns, ty0 + i / columns, p->blur_permutations);
    for (uint block = 0; block < k * k; ++block) {
        uint2 pixel[REYES_BLUR_CACHED_TILES];
        uint count = 0;
        for (uint i = 0; i < tiles; ++i) {
            uint slot = reyes_slot_of_block(perm[i], block, k);
            uint2 candidate = (uint2)((tx0 + i % columns) * k + slot % k, (ty0 + i / columns) * k + slot / k);
            if (reyes_pixel_in(candidate, swept))
                pixel[count++] = candidate;
        }
        for (uint s = 0; s < n && count > 0; ++s) {
            struct reyes_quad moved;
            float2 lo, hi;
            int4 r;
            if (!reyes_blur_move(b, q, block * n + s, &moved, &lo, &hi) || !reyes_tile_pixels(p, lo, hi, &r))
                continue;
            for (uint c = 0; c < count; ++c)
                if (reyes_pixel_in(pixel[c], r))
                    reyes_blur_sample(b, &moved, triangles, pixel[c].x, pixel[c].y, s);
        }
    }
}

/* interleaved: one pass per tuple of the pool.  The box swept over the
 * shutter and lens (widened by 1/20 pixel against rounding) bounds every
 * moved box, so a block none of whose pixels lies in it cannot cover
 * anything and is skipped: with boxes smaller than a tile most are. */
void reyes_blur_interleaved(const struct reyes_blur *b, const struct reyes_moving_quad *q, int triangles)
{
    __global const struct reyes_params *p = b->p;
    uint k = p->blur_tile;
    float2 swept_lo, swept_hi;
    int4 swept;
    int bounded = reyes_blur_box(p, q, triangles == 2 ? 4 : 3, &swept_lo, &swept_hi);
    if (bounded) {
        if (!reyes_tile_pixels(p, swept_lo - 0.05f, swept_hi + 0.05f, &swept))
            return;
        uint tiles = ((uint)swept.z / k - (uint)swept.x / k + 1u) * ((uint)swept.w / k - (uint)swept.y / k + 1u);
        if (tiles <= REYES_BLUR_CACHED_TILES) {
            reyes_blur_interleaved_cached(b, q, triangles, swept);
            return;
        }
    }
    for (uint block = 0; block < k * k; ++block) {
        if (bounded && !reyes_block_used(p, block, swept))
            continue;
        for (uint s = 0; s < p->spp; ++s)
            reyes_blur_interleaved_pass(b, q, triangles, block, s);
    }
}

/* bbox: every sample of every pixel in the box swept over the shutter and
 * the lens, each with the quad moved to its own tuple (the pattern
 * repeats every REYES_BLUR_BBOX_PERIOD pixels). */
void reyes_blur_bbox(const struct reyes_blur *b, const struct reyes_moving_quad *q, int triangles)
{
    __global const struct reyes_params *p = b->p;
    float2 lo, hi;
    int4 r;
    if (!reyes_blur_box(p, q, triangles == 2 ? 4 : 3, &lo, &hi)) {
        lo = (float2)(p->tile_x0, p->tile_y0);
        hi = (float2)(p->tile_x1, p->tile_y1);
    }
    if (!reyes_tile_pixels(p, lo, hi, &r))
        return;
    const uint period = REYES_BLUR_BBOX_PERIOD;
    uint n = p->spp;
    for (int py = r.y; py <= r.w; ++py) {
        for (int px = r.x; px <= r.z; ++px) {
            uint slot = ((uint)py % period) * period + (uint)px % period;
            for (uint s = 0; s < n; ++s) {
                struct reyes_quad moved;
                float2 moved_lo, moved_hi;
                if (reyes_blur_move(b, q, slot * n + s, &moved, &moved_lo, &moved_hi))
                    reyes_blur_sample(b, &moved, triangles, (uint)px, (uint)py, s);
            }
        }
    }
}

/* Rasterize a blurred quad (clip x, y, w and each vertex's motion;
 * triangles == 1: a stitch triangle, vertex 3 = vertex 0) with the
 * configured algorithm. */
void reyes_rasterize_blurred(__global const struct reyes_params *p, __global const float4 *tuples,
                             __global ulong *samples, const struct reyes_moving_quad *q, int triangles)
{
    struct reyes_blur b = { p, tuples, samples };
    if (p->blur_algo == REYES_BLUR_SIMPLE)
        reyes_blur_simple(&b, q, triangles);
    else if (p->blur_algo == REYES_BLUR_INTERLEAVED)
        reyes_blur_interleaved(&b, q, triangles);
    else
        reyes_blur_bbox(&b, q, triangles);
}
