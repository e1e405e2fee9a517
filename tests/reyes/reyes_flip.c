/* LDR-FLIP (reyes_flip.h): every filter is a sum of separable terms. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_flip.h"

#define PI 3.14159265358979323846

/* CIE D65 white, the reference of YCxCz and L*a*b*. */
static const double white[3] = {0.950428545, 1.0, 1.088900371};

static double srgb_to_linear(double c)
{
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

static void linear_to_xyz(const double rgb[3], double xyz[3])
{
    static const double m[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                   {0.2126729, 0.7151522, 0.0721750},
                                   {0.0193339, 0.1191920, 0.9503041}};
    for (int r = 0; r < 3; ++r)
        xyz[r] = m[r][0] * rgb[0] + m[r][1] * rgb[1] + m[r][2] * rgb[2];
}

static void xyz_to_linear(const double xyz[3], double rgb[3])
{
    static const double m[3][3] = {{3.2404542, -1.5371385, -0.4985314},
                                   {-0.9692660, 1.8760108, 0.0415560},
                                   {0.0556434, -0.2040259, 1.0572252}};
    for (int r = 0; r < 3; ++r)
        rgb[r] = m[r][0] * xyz[0] + m[r][1] * xyz[1] + m[r][2] * xyz[2];
}

/* The linear opponent space: L*a*b* without the cube root. */
static void xyz_to_ycxcz(const double xyz[3], double out[3])
{
    double x = xyz[0] / white[0], y = xyz[1], z = xyz[2] / white[2];
    out[0] = 116.0 * y - 16.0;
    out[1] = 500.0 * (x - y);
    out[2] = 200.0 * (y - z);
}

static void ycxcz_to_xyz(const double in[3], double xyz[3])
{
    double y = (in[0] + 16.0) / 116.0;
    xyz[0] = (y + in[1] / 500.0) * white[0];
    xyz[1] = y;
    xyz[2] = (y - in[2] / 200.0) * white[2];
}

static double lab_f(double t)
{
    const double delta = 6.0 / 29.0;
    return t > delta * delta * delta ? cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0;
}

/* Linear RGB to Hunt-adjusted L*a*b* (a and b scaled by L / 100). */
static void linear_to_hunt_lab(const double rgb[3], double lab[3])
{
    double xyz[3];
    linear_to_xyz(rgb, xyz);
    double fx = lab_f(xyz[0] / white[0]), fy = lab_f(xyz[1]), fz = lab_f(xyz[2] / white[2]);
    lab[0] = 116.0 * fy - 16.0;
    lab[1] = 0.01 * lab[0] * 500.0 * (fx - fy);
    lab[2] = 0.01 * lab[0] * 200.0 * (fy - fz);
}

static double hyab(const double a[3], const double b[3])
{
    return fabs(a[0] - b[0]) + hypot(a[1] - b[1], a[2] - b[2]);
}

/* One separable term: out += weight * (kx along x, then ky along y) of
 * in, borders replicated; kx and ky have 2 r + 1 taps. */
static void filter_add(const float *in, float *out, float *tmp, unsigned width, unsigned height,
                       const double *kx, const double *ky, int r, double weight)
{
    int w = (int)width, h = (int)height;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double sum = 0.0;
            for (int k = -r; k <= r; ++k) {
                int xx = x + k < 0 ? 0 : x + k >= w ? w - 1 : x + k;
                sum += kx[k + r] * in[(size_t)y * width + (size_t)xx];
            }
            tmp[(size_t)y * width + (size_t)x] = (float)sum;
        }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double sum = 0.0;
            for (int k = -r; k <= r; ++k) {
                int yy = y + k < 0 ? 0 : y + k >= h ? h - 1 : y + k;
                sum += ky[k + r] * tmp[(size_t)yy * width + (size_t)x];
            }
            out[(size_t)y * width + (size_t)x] += (float)(weight * sum);
        }
}

/* The contrast sensitivity filter of one opponent channel: a sum of two
 * Gaussians a sqrt(pi / b) exp(-pi^2 d^2 / b) (d in degrees), normalised
 * to sum 1 over the (2 r + 1)^2 taps. */
typedef struct csf {
    double a1, b1, a2, b2;
} csf;

static void csf_filter(const float *in, float *out, float *tmp, unsigned width, unsigned height, csf c,
                       double ppd, int r, double *g1, double *g2)
{
    double s1 = 0.0, s2 = 0.0;
    for (int k = -r; k <= r; ++k) {
        double d = (double)k / ppd;
        g1[k + r] = exp(-PI * PI * d * d / c.b1);
        g2[k + r] = exp(-PI * PI * d * d / c.b2);
        s1 += g1[k + r];
        s2 += g2[k + r];
    }
    double w1 = c.a1 * sqrt(PI / c.b1), w2 = c.a2 * sqrt(PI / c.b2);
    double total = w1 * s1 * s1 + w2 * s2 * s2;
    memset(out, 0, (size_t)width * height * sizeof *out);
    filter_add(in, out, tmp, width, height, g1, g1, r, w1 / total);
    if (w2 > 0.0)
        filter_add(in, out, tmp, width, height, g2, g2, r, w2 / total);
}

/* Edge (first derivative) or point (second derivative) detector of the
 * achromatic channel along x (transposed: along y), its positive taps
 * normalised to sum 1 and its negative ones to -1; the result's length
 * over both directions. */
static void feature_filter(const float *luminance, float *out, float *fx, float *fy, float *tmp, unsigned width,
                           unsigned height, double ppd, int point, double *d, double *g)
{
    double sd = 0.5 * 0.082 * ppd;
    int r = (int)ceil(3.0 * sd);
    double positive = 0.0, negative = 0.0, sum_g = 0.0;
    for (int k = -r; k <= r; ++k) {
        double x = (double)k, e = exp(-x * x / (2.0 * sd * sd));
        d[k + r] = point ? (x * x / (sd * sd) - 1.0) * e : -x * e;
        g[k + r] = e;
        sum_g += e;
        if (d[k + r] > 0.0)
            positive += d[k + r];
        else
            negative -= d[k + r];
    }
    for (int k = 0; k <= 2 * r; ++k) {
        d[k] = d[k] > 0.0 ? d[k] / positive : d[k] / negative;
        g[k] /= sum_g;
    }
    size_t n = (size_t)width * height;
    memset(fx, 0, n * sizeof *fx);
    memset(fy, 0, n * sizeof *fy);
    filter_add(luminance, fx, tmp, width, height, d, g, r, 1.0);
    filter_add(luminance, fy, tmp, width, height, g, d, r, 1.0);
    for (size_t k = 0; k < n; ++k)
        out[k] = hypotf(fx[k], fy[k]);
}

/* An image's opponent channels (3 planes) and its luminance Y. */
static void to_opponent(const uint8_t *rgb, size_t n, float *planes, float *luminance)
{
    for (size_t k = 0; k < n; ++k) {
        double linear[3], xyz[3], o[3];
        for (int c = 0; c < 3; ++c)
            linear[c] = srgb_to_linear(rgb[3 * k + (size_t)c] / 255.0);
        linear_to_xyz(linear, xyz);
        xyz_to_ycxcz(xyz, o);
        for (int c = 0; c < 3; ++c)
            planes[(size_t)c * n + k] = (float)o[c];
        luminance[k] = (float)xyz[1];
    }
}

/* Hunt-adjusted L*a*b* (3 planes) of filtered opponent planes, clamped
 * to the RGB cube first. */
static void filtered_to_lab(float *planes, size_t n)
{
    for (size_t k = 0; k < n; ++k) {
        double o[3] = {planes[k], planes[n + k], planes[2 * n + k]}, xyz[3], rgb[3], lab[3];
        ycxcz_to_xyz(o, xyz);
        xyz_to_linear(xyz, rgb);
        for (int c = 0; c < 3; ++c)
            rgb[c] = rgb[c] < 0.0 ? 0.0 : rgb[c] > 1.0 ? 1.0 : rgb[c];
        linear_to_hunt_lab(rgb, lab);
        for (int c = 0; c < 3; ++c)
            planes[(size_t)c * n + k] = (float)lab[c];
    }
}

double reyes_flip_mean(const uint8_t *reference, const uint8_t *test, unsigned width, unsigned height,
                       float pixels_per_degree, float *map)
{
    const csf filters[3] = {{1.0, 0.0047, 0.0, 1e-5}, {1.0, 0.0053, 0.0, 1e-5}, {34.1, 0.04, 13.5, 0.025}};
    double ppd = pixels_per_degree;
    int r = (int)ceil(3.0 * sqrt(0.04 / (2.0 * PI * PI)) * ppd);
    int taps = 2 * r + 1 > 2 * (int)ceil(3.0 * 0.5 * 0.082 * ppd) + 1 ? 2 * r + 1
                                                                       : 2 * (int)ceil(3.0 * 0.5 * 0.082 * ppd) + 1;
    size_t n = (size_t)width * height;
    float *buffer = malloc(n * 16 * sizeof *buffer);
    double *k1 = malloc((size_t)taps * sizeof *k1), *k2 = malloc((size_t)taps * sizeof *k2);
    if (!buffer || !k1 || !k2 || n == 0) {
        free(buffer);
        free(k1);
        free(k2);
        return n == 0 ? 0.0 : -1.0;
    }
    float *planes[2] = {buffer, buffer + 3 * n}, *filtered[2] = {buffer + 6 * n, buffer + 9 * n};
    float *luminance = buffer + 12 * n, *fx = buffer + 13 * n, *fy = buffer + 14 * n, *tmp = buffer + 15 * n;
    const uint8_t *images[2] = {reference, test};
    float *edges[2], *points[2];
    /* Features first, into the filtered planes' space (freed after). */
    for (int i = 0; i < 2; ++i) {
        to_opponent(images[i], n, planes[i], luminance);
        edges[i] = filtered[i];
        points[i] = filtered[i] + n;
        feature_filter(luminance, edges[i], fx, fy, tmp, width, height, ppd, 0, k1, k2);
        feature_filter(luminance, points[i], fx, fy, tmp, width, height, ppd, 1, k1, k2);
    }
    /* The feature difference, kept in fy (last use of the planes above). */
    for (size_t k = 0; k < n; ++k) {
        double e = fabs((double)edges[0][k] - edges[1][k]), p = fabs((double)points[0][k] - points[1][k]);
        fy[k] = (float)sqrt((e > p ? e : p) / sqrt(2.0));
    }
    for (int i = 0; i < 2; ++i) {
        for (int c = 0; c < 3; ++c)
            csf_filter(planes[i] + (size_t)c * n, filtered[i] + (size_t)c * n, tmp, width, height, filters[c], ppd,
                       r, k1, k2);
        filtered_to_lab(filtered[i], n);
    }
    double green[3] = {0.0, 1.0, 0.0}, blue[3] = {0.0, 0.0, 1.0}, lab_green[3], lab_blue[3];
    linear_to_hunt_lab(green, lab_green);
    linear_to_hunt_lab(blue, lab_blue);
    double cmax = pow(hyab(lab_green, lab_blue), 0.7), pc = 0.4, pt = 0.95, sum = 0.0;
    for (size_t k = 0; k < n; ++k) {
        double a[3] = {filtered[0][k], filtered[0][n + k], filtered[0][2 * n + k]};
        double b[3] = {filtered[1][k], filtered[1][n + k], filtered[1][2 * n + k]};
        double e = pow(hyab(a, b), 0.7);
        double colour = e < pc * cmax ? pt / (pc * cmax) * e : pt + (e - pc * cmax) / (cmax - pc * cmax) * (1.0 - pt);
        double flip = pow(colour, 1.0 - fy[k]);
        sum += flip;
        if (map)
            map[k] = (float)flip;
    }
    free(buffer);
    free(k1);
    free(k2);
    return sum / (double)n;
}
