/*
 * Types shared by the host and the OpenCL procedures of the Reyes renderer.
 * This file is compiled as C11 by the host and embedded verbatim into the
 * device program, so it may only use syntax both languages accept.
 */
#ifndef REYES_SHARED_H
#define REYES_SHARED_H

#ifdef __OPENCL_VERSION__
#define REYES_U32 uint
#else
#include <stdint.h>
#define REYES_U32 uint32_t
#endif

/* A rectangle [u0,u1] x [v0,v1] of a base patch's parameter domain: the
 * work item of bound and split (24 bytes instead of 16 control points). */
struct reyes_subpatch {
    REYES_U32 patch;  /* index of the base patch */
    REYES_U32 depth;  /* number of splits from the base patch */
    float u0, v0, u1, v1;
    /* Wedge and polyline crack fixes: the level at which each edge
     * settled, a byte per edge in REYES_EDGE_* order (0xff: not settled;
     * reyes_flatness.cl, reyes_polyline.cl); with a shading rate
     * otherwise each edge's segments (reyes_rate.cl). */
    REYES_U32 edge_levels;
    /* Shading-rate dicing (reyes_params.shading_rate > 0): the grid's
     * vertices along u (low byte) and v (next byte), chosen by bound; 0:
     * the renderer's grid x grid.  The polyline crack fix keeps each edge's
     * settled segment's pieces less 1 in the nibble at bit 16 + 4 edge. */
    REYES_U32 dice_size;
};

/* Set in a recorded leaf's dice_size by bound: its projected hull covers
 * no sample position (reyes_hull_has_sample), so it is not diced (its
 * edges still stitch). */
#define REYES_DICE_NO_SAMPLE 0x80000000u

/* One micropolygon: a grid quad in screen space (pixels, y down; z is the
 * camera-space depth) with a packed RGBA8 color per vertex.  Vertices go
 * around the quad: (i,j), (i+1,j), (i+1,j+1), (i,j+1). */
struct reyes_quad {
    float x[4];
    float y[4];
    float z[4];
    REYES_U32 rgba[4];
};

/* A micropolygon of a renderer made for per-vertex motion (a rotation
 * over the shutter, reyes_renderer_create): the quad (clip x, y, w when
 * blurred) and each vertex's own clip-space motion (x, y, w) from shutter
 * open to close.  A separate, larger item type so that every other
 * renderer keeps the 64-byte reyes_quad. */
struct reyes_moving_quad {
    struct reyes_quad quad;
    float mx[4];
    float my[4];
    float mw[4];
};

/* A diced sub-patch as recorded by bound when cracks are stitched (first
 * pass): the sub-patch and its control hull's screen box, for culling per
 * bucket on the host. */
struct reyes_leaf {
    struct reyes_subpatch sp;
    float lo_x, lo_y, hi_x, hi_y;
    float near_w; /* its control hull's nearest clip w: dice's front-to-back order */
};

/* Edges of a sub-patch, in the order of reyes_stitch.edge. */
#define REYES_EDGE_V0 0 /* v = v0, along u */
#define REYES_EDGE_U1 1 /* u = u1, along v */
#define REYES_EDGE_V1 2 /* v = v1, along u */
#define REYES_EDGE_U0 3 /* u = u0, along v */

/* One piece of an edge's neighbour: the neighbour sub-patch, which of its
 * edges touches, and whether it runs against the owner's edge direction. */
struct reyes_stitch_piece {
    struct reyes_subpatch sp;
    REYES_U32 edge;
    REYES_U32 reversed;
    float t0, t1;      /* the span it covers along the owner's edge, 0..1 */
};

/* The work item of the stitch procedure: one edge of a diced sub-patch
 * (the owner) and the neighbours' edges that cover a contiguous span of
 * it, pieces [first, first + count) of the piece buffer in the owner's
 * edge order. */
struct reyes_stitch {
    struct reyes_subpatch owner;
    REYES_U32 edge;
    REYES_U32 first;
    REYES_U32 count;
    REYES_U32 pad;
};

/* A diced grid (struct reyes_grid, reyes_grid.cl): REYES_GRID_HEADER_WORDS
 * words, then arrays of REYES_GRID_ARRAY(grid) vertices: x, y, z and
 * rgba, and with per-vertex motion also mx, my and mw.  An array holds a
 * grid x grid lattice or the four wedge strips of 2 x grid vertices,
 * rounded up to whole vectors of REYES_GRID_LANES, plus one vector of
 * padding that the SIMD code may read past the last vertex. */
#define REYES_GRID_HEADER_WORDS 11u
/* What a grid's rgba hold (reyes_grid.shading): the vertices' colours;
 * with sample shading their packed normals (displaced grids, whose
 * normals are central differences); or their packed parameters in the
 * grid's sub-patch and which way they face, each sample being lit with
 * the patch's own normal at its parameters (reyes_sample_shading.cl). */
#define REYES_SHADE_VERTICES 0u
#define REYES_SHADE_NORMALS 1u
#define REYES_SHADE_SURFACE 2u
#define REYES_GRID_LANES 16u
#define REYES_GRID_CAPACITY(n) ((n) >= 8u ? (n) * (n) : 8u * (n))
#define REYES_GRID_ARRAY(n) \
    ((REYES_GRID_CAPACITY(n) + REYES_GRID_LANES - 1u) / REYES_GRID_LANES * REYES_GRID_LANES + REYES_GRID_LANES)
#define REYES_GRID_VERTEX_WORDS 4u
#define REYES_GRID_MOVING_VERTEX_WORDS 7u

/* Indices into the statistics counter buffer. */
#define REYES_COUNT_SPLITS 0
#define REYES_COUNT_CULLED 1
#define REYES_COUNT_GRIDS 2
#define REYES_COUNT_MICROPOLYGONS 3
#define REYES_COUNT_FORCED_DICE 4 /* diced because the depth limit was hit */
#define REYES_COUNT_LEAVES 5      /* sub-patches recorded by bound (stitching) */
#define REYES_COUNT_FILLERS 6     /* crack-filling triangles rasterized by stitch */
/* Why bound split a sub-patch (they add up to REYES_COUNT_SPLITS): its
 * screen bound, its edge or inner tier (tiered criterion), or a hull
 * crossing the near plane (split in world space). */
#define REYES_COUNT_SPLIT_BOUND 7
#define REYES_COUNT_SPLIT_EDGE 8
#define REYES_COUNT_SPLIT_INNER 9
#define REYES_COUNT_SPLIT_NEAR 10
#define REYES_COUNT_OCCLUDED 11 /* grids dice skipped as hidden (reyes_occlusion.cl) */
/* With reyes_params.area_stats: the micropolygons' total screen area in
 * units of 2^-10 square pixels (a 64-bit count in words 12 and 13), and
 * how many fell in each of REYES_AREA_BINS bins by area: bin 0 below
 * 2^-10 square pixels, then half octaves starting at 2^e and 1.5 * 2^e,
 * bin 31 from 32 up (reyes_area_bin_lower). */
#define REYES_COUNT_AREA_SUM 12
#define REYES_COUNT_AREA_BINS 14
#define REYES_AREA_BINS 32
#define REYES_AREA_UNITS 1024.0f
#define REYES_COUNTERS (REYES_COUNT_AREA_BINS + REYES_AREA_BINS)

/* Subdivision criteria (reyes_params.subdivision). */
#define REYES_SUBDIVISION_BOUND 0
#define REYES_SUBDIVISION_TIERED 1

/* Displacement kinds (reyes_params.displace_mode). */
#define REYES_DISPLACE_NONE 0
#define REYES_DISPLACE_BUMPS 1
#define REYES_DISPLACE_MAP 2

/* Motion blur and defocus sampling algorithms (reyes_params.blur_algo,
 * reyes_blur.cl): one set of (time, lens) tuples for every pixel; K x K
 * tiles of pixels with their own tuples, permuted per tile; each pixel's
 * own tuples tested in the box swept over the shutter and lens. */
#define REYES_BLUR_SIMPLE 0
#define REYES_BLUR_INTERLEAVED 1
#define REYES_BLUR_BBOX 2
/* The bbox algorithm's tuples repeat every this many pixels in x and y. */
#define REYES_BLUR_BBOX_PERIOD 64

/* Which stages a render runs (reyes_params.stages), for timing stages by
 * difference: everything; bound, split and dice's geometry (positions and
 * visibility of the quads, what the C reference computes) without shading
 * or sampling; or bound and split only (dice just counts the grid). */
#define REYES_STAGES_ALL 0
#define REYES_STAGES_GEOMETRY 1
#define REYES_STAGES_SUBDIVIDE 2

/* The lighting of every render (reyes_params, set by reyes_render_params.c):
 * one directional light from the upper left behind the viewer (world
 * space, z up, normalised by the host), Lambert plus a Blinn-Phong
 * highlight.  reyes_shade (reyes_surface.cl) and its C mirror
 * reyes_reference_shade use them. */
#define REYES_LIGHT_X (-0.4f)
#define REYES_LIGHT_Y (-0.5f)
#define REYES_LIGHT_Z 0.77f
#define REYES_AMBIENT 0.18f
#define REYES_DIFFUSE 0.82f
#define REYES_SPECULAR 0.35f
#define REYES_SHININESS 40.0f

/* The hull tests of bound and dice, shared with the C reference: a
 * projected control hull's octagon (the screen box cut by the extremes of
 * x + y and x - y) with every side moved out by REYES_SAMPLE_BOX_MARGIN
 * pixels, how far dice's vertices may stray from it (rounding).  bound's
 * sampleless test (reyes_hull_has_sample) searches boxes of at most
 * REYES_SAMPLE_BOX_PIXELS pixels for a sample in it.  Occlusion culling
 * (reyes_occlusion.cl) tests hulls of at most REYES_OCCLUSION_PIXELS
 * pixels (it reads every sample under them), against a depth limit of
 * the hull's nearest clip w less a part of it (REYES_OCCLUSION_RELATIVE:
 * the rounding of the vertices' w) and REYES_OCCLUSION_ULPS float steps
 * of the w of points of the size of the scene's coordinates.  The
 * interpolation between vertices never goes below its corners' least w
 * (reyes_interpolated_depth, reyes_sample.cl), so it needs no margin.  A
 * wider margin keeps grids just behind the surface that hides them (1/256:
 * the killeroo seen small takes 4.7 micropolygons per covered pixel, not
 * 3.9). */
#define REYES_SAMPLE_BOX_MARGIN (1.0f / 64.0f)
#define REYES_SAMPLE_BOX_PIXELS 4
#define REYES_OCCLUSION_PIXELS 256
#define REYES_OCCLUSION_RELATIVE (1.0f / 4096.0f)
#define REYES_OCCLUSION_ULPS 64.0f

/* Scene and camera parameters, one per render (only scalars: the layout is
 * the same on host and device). */
struct reyes_params {
    float view_proj[16];   /* row-major: clip = view_proj * (x y z 1) */
    float eye[4];          /* camera position (w unused) */
    float light_dir[4];    /* unit vector towards the light (w unused) */
    float width, height;   /* image size in pixels */
    float bound_px;        /* dice when the screen bound is at most this */
    float cull_margin;     /* frustum tolerance, fraction of the half-viewport */
    float near_w;          /* clip w of the near plane */
    float ambient;         /* ambient light intensity */
    float diffuse;         /* Lambert weight */
    float specular;        /* Blinn-Phong weight */
    float shininess;       /* Blinn-Phong exponent */
    REYES_U32 max_depth;   /* splits after which a patch is diced anyway */
    REYES_U32 grid;        /* vertices per grid side */
    REYES_U32 spp;         /* samples per pixel */
    REYES_U32 backface_cull; /* 1: drop patches facing away entirely */
    REYES_U32 stages;        /* REYES_STAGES_* */
    /* 1: bound records the sub-patches to dice in the leaves buffer (up
     * to leaf_capacity, counted in REYES_COUNT_LEAVES) instead of emitting
     * them: the first pass of crack stitching. */
    REYES_U32 record_leaves;
    REYES_U32 leaf_capacity;
    /* The split rule (reyes_bound.cl): REYES_SUBDIVISION_BOUND dices at a
     * screen bound of bound_px; _TIERED (reyes_flatness.cl) dices when
     * every control-net curve is within flat_epsilon pixels of its
     * uniform chord (distance mix(geometric, full, flat_lambda)) and the
     * bound is at most flat_cap_px. */
    REYES_U32 subdivision;
    float flat_epsilon;
    float flat_lambda;
    float flat_cap_px;
    /* 1: crack fix by wedges (needs the tiered criterion): bound settles
     * every edge on a flat segment of its line, dice adds wedge strips
     * from its boundary to that segment's chord. */
    REYES_U32 wedges;
    /* Displacement (reyes_displace.cl): REYES_DISPLACE_*, the largest
     * distance, the bump frequency (per world unit) and the map size. */
    REYES_U32 displace_mode;
    float displace_amplitude;
    float displace_frequency;
    REYES_U32 map_width, map_height;
    /* Motion blur and depth of field (rasterize, reyes_blur.cl): when
     * blur is 1, quads carry clip-space x, y, w and each sample has its
     * own time t in [0,1) (time_samples strata) and lens position; a
     * vertex at time t and lens (lx, ly) in the unit disk is at
     * clip + t * motion_clip + (w_t / focus - 1) * (lx * lens_x, ly * lens_y).
     * motion_clip is the vertex's own: motion_rows (rows x, y, w of a 3x4
     * affine map, row-major) applied to its world position (x y z 1).
     * Without a rotation the map is constant, its last column (entries
     * 3, 7, 11), the same for every vertex. */
    REYES_U32 blur;
    REYES_U32 time_samples;
    float motion_rows[12]; /* world position -> clip-space motion (x, y, w) */
    REYES_U32 motion_rotates; /* 1: motion_rows depends on the position */
    REYES_U32 pad4;
    float lens_x, lens_y;  /* aperture radius in clip x and y units per unit w */
    float focus;           /* view depth in focus */
    float pad2;
    /* REYES_BLUR_*; interleaved: tile side K and number of permutations P. */
    REYES_U32 blur_algo;
    REYES_U32 blur_tile;
    REYES_U32 blur_permutations;
    REYES_U32 pad3;
    /* The bucket (tile) this run renders, in pixels: [tile_x0,tile_x1) x
     * [tile_y0,tile_y1) (the whole image without buckets).  The sample
     * buffer holds the tile's pixels only; sample positions stay those of
     * the global pixel. */
    float tile_x0, tile_y0, tile_x1, tile_y1;
    /* The tile's sub-frustum in normalised device coordinates (x right, y
     * up): -1, 1, -1, 1 for the whole image.  bound culls against it with
     * the cull margin. */
    float ndc_left, ndc_right, ndc_bottom, ndc_top;
    /* Shading-rate dicing: 0 dices every leaf grid x grid; R > 0 dices
     * each to the fewest vertices (up to grid per side) whose
     * micropolygons are at most R pixels in area on screen, and bound
     * splits a sub-patch until that fits (reyes_bound.cl). */
    float shading_rate;
    /* 1: shade every grid in a false colour by its size instead of its
     * patch's colour (reyes_options.show_grid_sizes). */
    REYES_U32 show_grid_sizes;
    /* 1 (with a shading rate and no blur): shade every sample, not every
     * vertex.  dice stores each vertex's unit normal (reyes_pack_normal)
     * where it would store its colour, and rasterize and stitch light
     * each covered sample with the normal interpolated from its
     * triangle's vertices, seen along the sample's own ray: its direction
     * is ray_origin + x ray_dx + y ray_dy (world space, away from the
     * eye) for the sample at pixel coordinates (x, y). */
    REYES_U32 sample_shading;
    REYES_U32 area_stats;   /* 1: rasterize counts micropolygon areas (REYES_COUNT_AREA_*) */
    float ray_origin[4], ray_dx[4], ray_dy[4];
    /* Shading-rate counts (reyes_rate.cl): how far a piece's chord may
     * stray from its curve on screen (pixels), and the shortest piece
     * that bending asks for, in sides of the rate in space. */
    float rate_sag, rate_min_piece;
    /* 1: dice skips a grid that the samples already hold nearer surfaces
     * over (reyes_grid_occluded, reyes_occlusion.cl); only with a shading
     * rate, undisplaced, unblurred, without wedges, in full renders. */
    REYES_U32 occlusion_cull;
    /* 1: crack fix by polylines (reyes_polyline.cl; with a shading rate):
     * bound settles every edge on a segment of its base patch's line
     * that both sides choose alone, dice puts that segment's polyline on
     * the edge and fills the T-junctions. */
    REYES_U32 polyline;
};

#endif
