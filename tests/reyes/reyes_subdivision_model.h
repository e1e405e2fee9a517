/*
 * A subdivision-surface test model made in code: a cube cage, made lumpy
 * and refined by Catmull-Clark subdivision, each quad of the final mesh
 * converted to a bicubic Bézier patch (Loop and Schaefer's approximation:
 * exact for faces whose corners have valence 4, where Catmull-Clark is the
 * uniform bicubic B-spline; the eight corners of the cube stay valence 3).
 * Many small patches with base-patch borders everywhere: what the crack
 * tests need beside the models of ../shared.
 */
#ifndef REYES_SUBDIVISION_MODEL_H
#define REYES_SUBDIVISION_MODEL_H

#include "reyes.h"

/* Add the model (6 * 4^levels patches; levels 1..6) to scene in colour
 * rgba.  The lumps are a fixed hash of the vertices, about a tenth of the
 * model's size.  glued: neighbouring patches share their boundary
 * control points bit for bit; else every other patch rounds its control
 * points to float the other way, so that shared boundaries agree only to
 * the last bit, as in models whose patches were converted one by one
 * (296 of the killeroo's boundary curves meet their neighbour's only to
 * rounding). */
reyes_status reyes_subdivision_model_add(reyes_scene *scene, unsigned levels, int glued, uint32_t rgba,
                                         reyes_error *error);

/* The same from another cage: REYES_CAGE_CUBE (the above: valences 3 and
 * 4) or REYES_CAGE_ICOSAHEDRAL (240 quads around an icosahedron whose
 * vertices have valence 3, 4, 5 and 6: 240 * 4^levels patches, base
 * patch corners where 3 to 6 patches meet). */
enum { REYES_CAGE_CUBE, REYES_CAGE_ICOSAHEDRAL };
reyes_status reyes_subdivision_cage_add(reyes_scene *scene, unsigned cage, unsigned levels, int glued, uint32_t rgba,
                                        reyes_error *error);

#endif
