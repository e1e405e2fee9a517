/* OpenCL sources of the Reyes procedures, embedded at build time. */
#ifndef REYES_SOURCES_H
#define REYES_SOURCES_H

extern const char reyes_shared_h_source[];
extern const char reyes_common_cl_source[];
extern const char reyes_bound_cl_source[];
extern const char reyes_flatness_cl_source[];
extern const char reyes_rate_cl_source[];
extern const char reyes_split_u_cl_source[];
extern const char reyes_split_v_cl_source[];
extern const char reyes_dice_cl_source[];
extern const char reyes_rasterize_cl_source[];
extern const char reyes_sample_cl_source[];
extern const char reyes_sample_shading_cl_source[];
extern const char reyes_blur_cl_source[];
extern const char reyes_displace_cl_source[];
extern const char reyes_surface_cl_source[];
extern const char reyes_grid_cl_source[];
extern const char reyes_stitch_cl_source[];

#endif
