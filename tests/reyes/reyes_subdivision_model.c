/* The subdivision-surface test model (reyes_subdivision_model.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_subdivision_model.h"

/* A closed quad mesh; faces counter-clockwise seen from outside. */
typedef struct mesh {
    double (*v)[3];
    unsigned (*f)[4];
    size_t vertices, faces;
} mesh;

/* An undirected edge: its end points (a < b) and the faces on either side. */
typedef struct edge {
    unsigned a, b;
    unsigned face[2];
    unsigned corner[2]; /* the corner of face[k] where the edge starts */
} edge;

static int compare_edges(const void *pa, const void *pb)
{
    const edge *x = pa, *y = pb;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    return x->b < y->b ? -1 : x->b > y->b;
}

/* The mesh's edges, each with both faces (the mesh is closed). */
static edge *mesh_edges(const mesh *m, size_t *count)
{
    size_t n = m->faces * 4;
    edge *half = malloc(n * sizeof *half), *edges = malloc(n / 2 * sizeof *edges);
    if (!half || !edges) {
        free(half);
        free(edges);
        return NULL;
    }
    for (size_t f = 0; f < m->faces; ++f)
        for (unsigned i = 0; i < 4; ++i) {
            unsigned a = m->f[f][i], b = m->f[f][(i + 1) % 4];
            half[f * 4 + i] = (edge){ a < b ? a : b, a < b ? b : a, {(unsigned)f, 0}, {i, 0} };
        }
    qsort(half, n, sizeof *half, compare_edges);
    for (size_t k = 0; k + 1 < n; k += 2) {
        edges[k / 2] = half[k];
        edges[k / 2].face[1] = half[k + 1].face[0];
        edges[k / 2].corner[1] = half[k + 1].corner[0];
    }
    free(half);
    *count = n / 2;
    return edges;
}

/* The index of edge (a, b) in the sorted edges. */
static size_t find_edge(const edge *edges, size_t count, unsigned a, unsigned b)
{
    edge key = { a < b ? a : b, a < b ? b : a, {0, 0}, {0, 0} };
    const edge *e = bsearch(&key, edges, count, sizeof *edges, compare_edges);
    return (size_t)(e - edges);
}

static void mesh_free(mesh *m)
{
    free(m->v);
    free(m->f);
    memset(m, 0, sizeof *m);
}

/* One Catmull-Clark step of a closed quad mesh. */
static int catmull_clark(const mesh *m, mesh *out)
{
    size_t ne;
    edge *edges = mesh_edges(m, &ne);
    size_t nv = m->vertices + ne + m->faces;
    out->v = calloc(nv, sizeof *out->v);
    out->f = malloc(m->faces * 4 * sizeof *out->f);
    double (*sum_f)[3] = calloc(m->vertices, sizeof *sum_f), (*sum_e)[3] = calloc(m->vertices, sizeof *sum_e);
    unsigned *valence = calloc(m->vertices, sizeof *valence);
    if (!edges || !out->v || !out->f || !sum_f || !sum_e || !valence) {
        free(edges);
        free(sum_f);
        free(sum_e);
        free(valence);
        mesh_free(out);
        return 0;
    }
    out->vertices = nv;
    out->faces = m->faces * 4;
    size_t face_base = m->vertices + ne;
    for (size_t f = 0; f < m->faces; ++f) {
        double *fp = out->v[face_base + f];
        for (int i = 0; i < 4; ++i)
            for (int k = 0; k < 3; ++k)
                fp[k] += 0.25 * m->v[m->f[f][i]][k];
        for (int i = 0; i < 4; ++i)
            for (int k = 0; k < 3; ++k)
                sum_f[m->f[f][i]][k] += fp[k];
    }
    for (size_t e = 0; e < ne; ++e) {
        double *ep = out->v[m->vertices + e];
        const double *a = m->v[edges[e].a], *b = m->v[edges[e].b];
        const double *f0 = out->v[face_base + edges[e].face[0]], *f1 = out->v[face_base + edges[e].face[1]];
        for (int k = 0; k < 3; ++k) {
            ep[k] = 0.25 * (a[k] + b[k] + f0[k] + f1[k]);
            sum_e[edges[e].a][k] += 0.5 * (a[k] + b[k]);
            sum_e[edges[e].b][k] += 0.5 * (a[k] + b[k]);
        }
        ++valence[edges[e].a];
        ++valence[edges[e].b];
    }
    for (size_t v = 0; v < m->vertices; ++v) {
        double n = valence[v];
        for (int k = 0; k < 3; ++k)
            out->v[v][k] = (sum_f[v][k] / n + 2.0 * sum_e[v][k] / n + (n - 3.0) * m->v[v][k]) / n;
    }
    for (size_t f = 0; f < m->faces; ++f)
        for (unsigned i = 0; i < 4; ++i) {
            unsigned a = m->f[f][i], next = m->f[f][(i + 1) % 4], prev = m->f[f][(i + 3) % 4];
            unsigned *q = out->f[f * 4 + i];
            q[0] = a;
            q[1] = (unsigned)(m->vertices + find_edge(edges, ne, a, next));
            q[2] = (unsigned)(face_base + f);
            q[3] = (unsigned)(m->vertices + find_edge(edges, ne, prev, a));
        }
    free(edges);
    free(sum_f);
    free(sum_e);
    free(valence);
    return 1;
}

static int make_cube(mesh *m)
{
    static const double corners[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                         {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    static const unsigned faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                         {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    m->v = malloc(sizeof corners);
    m->f = malloc(sizeof faces);
    if (!m->v || !m->f) {
        mesh_free(m);
        return 0;
    }
    memcpy(m->v, corners, sizeof corners);
    memcpy(m->f, faces, sizeof faces);
    m->vertices = 8;
    m->faces = 6;
    return 1;
}

/* A quad cage whose vertices have valence 3, 4, 5 and 6: an icosahedron,
 * each triangle cut into four (the new vertices have valence 6), each of
 * those cut into three quads from its centre (valence 3) to its edges'
 * midpoints (valence 4); the icosahedron's corners keep valence 5. */
static int make_icosahedral(mesh *m)
{
    const double g = (1.0 + sqrt(5.0)) / 2.0;
    double v[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                       {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    static const unsigned t[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                      {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                      {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                      {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    /* 80 triangles of 12 + 30 vertices, each 3 quads with a centre and
     * three midpoints: at most 42 + 80 + 240 vertices (midpoints shared by
     * looking them up). */
    size_t cap = 42 + 80 + 240;
    m->v = calloc(cap, sizeof *m->v);
    m->f = malloc(240 * sizeof *m->f);
    unsigned (*tri)[3] = malloc(80 * sizeof *tri);
    if (!m->v || !m->f || !tri) {
        free(tri);
        mesh_free(m);
        return 0;
    }
    m->vertices = 0;
    for (int k = 0; k < 12; ++k)
        memcpy(m->v[m->vertices++], v[k], sizeof v[k]);
    /* The midpoint of (a, b), found among the vertices or added. */
#define MIDPOINT(a, b, out)                                                                                   do {                                                                                                          double mid[3];                                                                                            for (int k = 0; k < 3; ++k)                                                                                   mid[k] = 0.5 * (m->v[a][k] + m->v[b][k]);                                                            size_t found = m->vertices;                                                                               for (size_t i = 0; i < m->vertices; ++i)                                                                      if (m->v[i][0] == mid[0] && m->v[i][1] == mid[1] && m->v[i][2] == mid[2])                                     found = i;                                                                                        if (found == m->vertices)                                                                                     memcpy(m->v[m->vertices++], mid, sizeof mid);                                                         (out) = (unsigned)found;                                                                              } while (0)
    size_t tris = 0;
    for (int f = 0; f < 20; ++f) {
        unsigned a = t[f][0], b = t[f][1], c = t[f][2], ab, bc, ca;
        MIDPOINT(a, b, ab);
        MIDPOINT(b, c, bc);
        MIDPOINT(c, a, ca);
        const unsigned four[4][3] = {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}};
        memcpy(tri[tris], four, sizeof four);
        tris += 4;
    }
    m->faces = 0;
    for (size_t f = 0; f < tris; ++f) {
        unsigned a = tri[f][0], b = tri[f][1], c = tri[f][2], ab, bc, ca;
        MIDPOINT(a, b, ab);
        MIDPOINT(b, c, bc);
        MIDPOINT(c, a, ca);
        unsigned centre = (unsigned)m->vertices++;
        for (int k = 0; k < 3; ++k)
            m->v[centre][k] = (m->v[a][k] + m->v[b][k] + m->v[c][k]) / 3.0;
        const unsigned quads[3][4] = {{a, ab, centre, ca}, {b, bc, centre, ab}, {c, ca, centre, bc}};
        memcpy(m->f[m->faces], quads, sizeof quads);
        m->faces += 3;
    }
#undef MIDPOINT
    free(tri);
    /* Onto the unit sphere, as the cube's corners lie on one. */
    for (size_t i = 0; i < m->vertices; ++i) {
        double r = sqrt(m->v[i][0] * m->v[i][0] + m->v[i][1] * m->v[i][1] + m->v[i][2] * m->v[i][2]);
        for (int k = 0; k < 3; ++k)
            m->v[i][k] *= sqrt(3.0) / r;
    }
    return 1;
}

/* Move every vertex along its direction from the centre by up to
 * `amount` of its distance, a fixed hash of its index. */
static void lumps(mesh *m, double amount, uint32_t seed)
{
    for (size_t v = 0; v < m->vertices; ++v) {
        uint32_t h = (uint32_t)v * 2654435761u ^ seed;
        h ^= h >> 15;
        h *= 0x2c1b3c6du;
        h ^= h >> 12;
        double t = (double)(h & 0xffffu) / 65535.0 * 2.0 - 1.0;
        for (int k = 0; k < 3; ++k)
            m->v[v][k] *= 1.0 + amount * t;
    }
}

/* Bézier control points of every face (Loop and Schaefer): corners at the
 * vertices' limit positions, interior points (n v + 2 (m1 + m2) + d) /
 * (n + 5) for a corner v of valence n with its neighbours m1, m2 and the
 * diagonal d in the face, and edge points the mean of the two interior
 * points next to them.  Each corner and edge point is computed once and
 * shared by the faces around it, so the patches' boundaries agree bit for
 * bit when rounded to float, unless not `glued`. */
static reyes_status add_patches(const mesh *m, reyes_scene *scene, uint32_t rgba, int glued, reyes_error *error)
{
    size_t ne;
    edge *edges = mesh_edges(m, &ne);
    double (*limit)[3] = calloc(m->vertices, sizeof *limit), (*inner)[3] = calloc(m->faces * 4, sizeof *inner);
    double (*edge_point)[2][3] = calloc(ne, sizeof *edge_point);
    unsigned *valence = calloc(m->vertices, sizeof *valence);
    reyes_status status = REYES_OK;
    if (!edges || !limit || !inner || !edge_point || !valence)
        status = reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for a subdivision model of %zu faces",
                            m->faces);
    for (size_t f = 0; status == REYES_OK && f < m->faces; ++f)
        for (int i = 0; i < 4; ++i)
            ++valence[m->f[f][i]];
    for (size_t f = 0; status == REYES_OK && f < m->faces; ++f)
        for (int i = 0; i < 4; ++i) {
            unsigned v = m->f[f][i];
            const double *x = m->v[v], *next = m->v[m->f[f][(i + 1) % 4]], *diagonal = m->v[m->f[f][(i + 2) % 4]];
            const double *prev = m->v[m->f[f][(i + 3) % 4]];
            double n = valence[v];
            for (int k = 0; k < 3; ++k) {
                inner[f * 4 + (size_t)i][k] = (n * x[k] + 2.0 * (next[k] + prev[k]) + diagonal[k]) / (n + 5.0);
                /* Limit position: (n^2 v + 4 sum of neighbours + sum of diagonals) / (n (n + 5)),
                 * each face adding one neighbour (next) and one diagonal. */
                limit[v][k] += (4.0 * next[k] + diagonal[k]) / (n * (n + 5.0));
            }
        }
    for (size_t v = 0; status == REYES_OK && v < m->vertices; ++v) {
        double n = valence[v];
        for (int k = 0; k < 3; ++k)
            limit[v][k] += n * m->v[v][k] / (n + 5.0);
    }
    for (size_t e = 0; status == REYES_OK && e < ne; ++e) {
        /* End a (0) and b (1): the inner points at that corner of both faces. */
        for (int end = 0; end < 2; ++end) {
            unsigned v = end ? edges[e].b : edges[e].a;
            for (int k = 0; k < 3; ++k) {
                double sum = 0.0;
                for (int side = 0; side < 2; ++side) {
                    unsigned f = edges[e].face[side], c = edges[e].corner[side];
                    unsigned corner = m->f[f][c] == v ? c : (c + 1) % 4;
                    sum += inner[(size_t)f * 4 + corner][k];
                }
                edge_point[e][end][k] = 0.5 * sum;
            }
        }
    }
    for (size_t f = 0; status == REYES_OK && f < m->faces; ++f) {
        const unsigned *q = m->f[f];
        double cp[4][4][3];
        /* u runs q0 -> q1 along row 0, v runs q0 -> q3 along column 0. */
        static const int corner_at[4][2] = {{0, 0}, {0, 3}, {3, 3}, {3, 0}};
        static const int inner_at[4][2] = {{1, 1}, {1, 2}, {2, 2}, {2, 1}};
        for (int i = 0; i < 4; ++i) {
            memcpy(cp[corner_at[i][0]][corner_at[i][1]], limit[q[i]], sizeof cp[0][0]);
            memcpy(cp[inner_at[i][0]][inner_at[i][1]], inner[f * 4 + (size_t)i], sizeof cp[0][0]);
            /* Edge q_i -> q_{i+1}: its point next to each end, placed one
             * step from that end's corner towards the other's. */
            unsigned a = q[i], b = q[(i + 1) % 4];
            size_t e = find_edge(edges, ne, a, b);
            const int *from = corner_at[i], *to = corner_at[(i + 1) % 4];
            int dr = (to[0] > from[0]) - (to[0] < from[0]), dc = (to[1] > from[1]) - (to[1] < from[1]);
            memcpy(cp[from[0] + dr][from[1] + dc], edge_point[e][a == edges[e].b], sizeof cp[0][0]);
            memcpy(cp[to[0] - dr][to[1] - dc], edge_point[e][b == edges[e].b], sizeof cp[0][0]);
        }
        float points[4][4][3];
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c)
                for (int k = 0; k < 3; ++k) {
                    float x = (float)cp[r][c][k];
                    /* Not glued: this patch rounds its own way, to the
                     * float on the other side of the exact value in every
                     * other patch. */
                    if (!glued && (f & 1u) && (double)x != cp[r][c][k])
                        x = nextafterf(x, (double)x < cp[r][c][k] ? INFINITY : -INFINITY);
                    points[r][c][k] = x;
                }
        status = reyes_scene_add_patch(scene, points, rgba, error);
    }
    free(edges);
    free(limit);
    free(inner);
    free(edge_point);
    free(valence);
    return status;
}

reyes_status reyes_subdivision_model_add(reyes_scene *scene, unsigned levels, int glued, uint32_t rgba,
                                         reyes_error *error)
{
    return reyes_subdivision_cage_add(scene, REYES_CAGE_CUBE, levels, glued, rgba, error);
}

reyes_status reyes_subdivision_cage_add(reyes_scene *scene, unsigned cage, unsigned levels, int glued, uint32_t rgba,
                                        reyes_error *error)
{
    if (levels < 1 || levels > 6)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "subdivision model levels %u is not in 1..6", levels);
    if (cage > REYES_CAGE_ICOSAHEDRAL)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "subdivision cage %u is not %u (cube) or %u (icosahedral)", cage,
                          REYES_CAGE_CUBE, REYES_CAGE_ICOSAHEDRAL);
    mesh m = {0};
    if (!(cage == REYES_CAGE_CUBE ? make_cube(&m) : make_icosahedral(&m)))
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for a subdivision cage");
    for (unsigned level = 0; level < levels; ++level) {
        /* Lumps on the first two refinements: a few large, then smaller. */
        if (level == 1)
            lumps(&m, 0.25, 0x9e3779b9u);
        if (level == 2)
            lumps(&m, 0.08, 0x7f4a7c15u);
        mesh next = {0};
        int ok = catmull_clark(&m, &next);
        mesh_free(&m);
        if (!ok)
            return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory subdividing level %u", level + 1);
        m = next;
    }
    reyes_status status = add_patches(&m, scene, rgba, glued, error);
    mesh_free(&m);
    return status;
}
