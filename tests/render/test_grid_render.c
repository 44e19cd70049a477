/* test_grid_render.c: the renderer and the library on a graded grid
 * (rod.refine, sim/rod_grid.h). A recording carries its nodes' arc lengths
 * (rod_recording.arc); what the picture computes along the rod counts them,
 * not the node's index:
 * - the (4.17) stripe's phase at node i is s_i u3 (s_i the graded arc,
 *   from the grid's formula here, not i ds);
 * - the curvature colour of a helix (constant Darboux vector, so curvature
 *   kappa at every node) is kappa at every node of a graded grid;
 * - the same helix drawn from a graded grid of 81 nodes is as close to its
 *   picture on a fine uniform grid (321 nodes, PSNR) as a uniform grid of
 *   the graded one's longest segment (51 nodes) is (the tube follows the
 *   nodes; the colour, the stripe and the strands' shading count arc);
 * - `rodsim run` draws a graded scene's video (exit 0, not 2), and the
 *   library loads a graded scene, steps it and gives the nodes' arc
 *   lengths (rodsim_node_arc) equal to rod_node_arc and the grid's formula. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "render/color.h"
#include "render/geometry.h"
#include "render/image.h"
#include "render/render.h"
#include "render/renderer.h"
#include "rodsim.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"
#include "synthetic_recording.h"
#include "test.h"
#include "test_process.h"
#include "test_scene_run.h"

#define NODES 81
#define FINE_NODES 321
#define COARSE_NODES 51 /* ds 0.02 m: the graded grid's segments outside its interval */
#define WIDTH 640
#define HEIGHT 360

/* The graded grid of refine = 0.3 0.5 4 on L = 1 m by its formula: the
 * nodes equally spaced in the stretched arc S(s) = s + 3 |[0.3, 0.5] below
 * s|, S(L) = 1.6 m; s(S) inverted piecewise. */
static double graded_arc(int i, int nodes)
{
    const double stretched = i * 1.6 / (nodes - 1);
    if (stretched <= 0.3) return stretched;
    if (stretched <= 1.1) return 0.3 + (stretched - 0.3) / 4.0;
    return 0.5 + (stretched - 1.1);
}

/* The helix of constant Darboux vector u = (kappa, 0, tau) (body frame):
 * Q(s) = Q0 exp(s [u]x), r(s) = Q0 int_0^s exp(t [u]x) e3 dt in closed form
 * (Rodrigues: with a = u / w, w = |u|, (a.e3) a s + sin(w s) / w (e3 -
 * (a.e3) a) + (1 - cos(w s)) / w a x e3). Radius kappa / w^2, pitch
 * 2 pi tau / w^2. */
#define HELIX_KAPPA 12.42
#define HELIX_TAU 0.989
static double helix_u[3] = {HELIX_KAPPA, 0, HELIX_TAU}; /* the helix drawn */
static void helix_at(double s, double r[3], double q[9])
{
    static const double q0[9] = {0, 0, 1, 1, 0, 0, 0, 1, 0}; /* d1 = y, d2 = z, d3 = x */
    const double *u = helix_u, e3[3] = {0, 0, 1};
    const double w = v3_norm(u);
    double a[3], phi[3], turn[9], local[3], across[3];
    v3_scale(a, u, 1.0 / w);
    v3_scale(phi, u, s);
    m3_exp(turn, phi);
    m3_mul(q, q0, turn);
    v3_cross(across, a, e3);
    for (int c = 0; c < 3; c++)
        local[c] = a[2] * a[c] * s + sin(w * s) / w * (e3[c] - a[2] * a[c]) +
                   (1 - cos(w * s)) / w * across[c];
    m3_mul_v(r, q0, local);
}

/* A recording of one frame: the helix at the nodes' arc lengths (graded:
 * the formula's, carried in rec->arc; else i ds), u3 = twist at each. */
static rod_recording *helix_recording(int nodes, int graded, double twist)
{
    rod_recording *rec = synthetic_recording_create(nodes, 1, 1.0, 0.01);
    if (graded) {
        rec->arc = malloc((size_t)nodes * sizeof *rec->arc);
        for (int i = 0; i < nodes; i++) rec->arc[i] = graded_arc(i, nodes);
    }
    for (int i = 0; i < nodes; i++) {
        helix_at(rod_recording_arc(rec, i), &rec->position[3 * i], &rec->frame[9 * i]);
        rec->twist[i] = twist;
    }
    return rec;
}

static void test_stripe_phase(void)
{
    const double u3 = 7.3;
    rod_recording *rec = helix_recording(NODES, 1, u3);
    double worst = 0.0, index_worst = 0.0;
    int at = 0;
    for (int i = 0; i < NODES; i++) {
        const double s = graded_arc(i, NODES);
        double offset[3];
        stripe_formula_offset(rec, 0, i, offset);
        const double want[3] = {0, -sin(s * u3), cos(s * u3)};
        double d[3];
        v3_sub(d, offset, want);
        if (v3_norm(d) > worst) worst = v3_norm(d), at = i;
        /* what i ds would give: the phase the graded grid must not take */
        const double wrong = fabs(sin(0.5 * (i * rec->ds - s) * u3)) * 2.0;
        index_worst = fmax(index_worst, wrong);
    }
    check(worst < 1e-12,
          "the (4.17) stripe's offset at node i is (0, -sin s_i u3, cos s_i u3), s_i the graded "
          "arc: largest distance %.3e at node %d (tolerance 1e-12; the phase i ds would be "
          "%.3f off)", worst, at, index_worst);
    check(index_worst > 0.5, "the graded grid's phase differs from i ds's (by up to %.3f)",
          index_worst);
    rod_recording_destroy(rec);
}

static void test_curvature_colour(void)
{
    const double w2 = HELIX_KAPPA * HELIX_KAPPA + HELIX_TAU * HELIX_TAU;
    printf("helix: radius %.4f m, pitch %.4f m, curvature %.4f 1/m\n", HELIX_KAPPA / w2,
           2 * M_PI * HELIX_TAU / w2, HELIX_KAPPA);
    for (int graded = 0; graded < 2; graded++) {
        rod_recording *rec = helix_recording(NODES, graded, 0.0);
        double values[NODES], worst = 0.0;
        color_values(rec, 0, RENDER_COLOR_CURVATURE, NULL, 0.0, values);
        int at = 0;
        for (int i = 0; i < NODES; i++)
            if (fabs(values[i] - HELIX_KAPPA) > worst) worst = fabs(values[i] - HELIX_KAPPA), at = i;
        char what[160];
        snprintf(what, sizeof what, "%s grid: the curvature colour's value at node %d (the "
                 "farthest from kappa)", graded ? "graded" : "uniform", at);
        check_rel(what, values[at], HELIX_KAPPA, 1e-9);
        rod_recording_destroy(rec);
    }
}

/* The picture of rec with a fixed camera (no shadow, no overlay): the
 * curvature colour, the (4.17) stripe. NULL when it cannot be drawn. */
static image *draw_view(const rod_recording *rec, const double look_at[3], const double view[3],
                        double distance, render_color_mode color)
{
    render_options o;
    render_options_default(&o);
    o.width = WIDTH;
    o.height = HEIGHT;
    o.grid = 0;
    o.overlay = 0;
    o.arrows = 0;
    o.shadows = 0;
    o.color = color;
    o.color_range[0] = 0.0;
    o.color_range[1] = 20.0;
    o.stripe = RENDER_STRIPE_FORMULA;
    o.camera_keys.has_look_at = 1;
    v3_copy(o.camera_keys.look_at, look_at);
    o.camera_keys.has_view = 1;
    v3_copy(o.camera_keys.view, view);
    o.camera_keys.distance = distance;
    o.directed = 1; /* the camera keys above, not a fit to the nodes */
    renderer r;
    char err[1024] = "";
    if (renderer_create(&r, rec, &o, "grid", &frame_band_full, err, sizeof err)) {
        printf("renderer: %s\n", err);
        return NULL;
    }
    image *img = image_create(WIDTH, HEIGHT);
    if (img && renderer_draw(&r, rec, 0, img)) {
        image_destroy(img);
        img = NULL;
    }
    renderer_destroy(&r);
    return img;
}

static image *draw(const rod_recording *rec, const double look_at[3])
{
    const double view[3] = {0.3, -1.0, 0.5};
    return draw_view(rec, look_at, view, 0.6, RENDER_COLOR_CURVATURE);
}

static double psnr(const image *a, const image *b)
{
    const size_t n = (size_t)a->width * (size_t)a->height * 3;
    double sum = 0.0;
    for (size_t k = 0; k < n; k++) {
        const double d = (double)a->rgb[k] - (double)b->rgb[k];
        sum += d * d;
    }
    return sum > 0 ? 10.0 * log10(255.0 * 255.0 / (sum / n)) : INFINITY;
}

/* Pixels that differ from the background (the top-left pixel's colour). */
static int drawn_pixels(const image *a)
{
    int count = 0;
    for (int k = 0; k < a->width * a->height; k++)
        count += memcmp(&a->rgb[3 * k], a->rgb, 3) != 0;
    return count;
}

static void test_frames_agree(void)
{
    enum { UNIFORM, GRADED, COARSE, FINE, KINDS };
    const int nodes[KINDS] = {NODES, NODES, COARSE_NODES, FINE_NODES};
    const char *names[KINDS] = {"uniform", "graded", "coarse", "fine"};
    rod_recording *rec[KINDS];
    image *img[KINDS];
    for (int k = 0; k < KINDS; k++) rec[k] = helix_recording(nodes[k], k == GRADED, 9.0);
    double centre[3] = {0, 0, 0}; /* the fine grid's nodes' mean */
    for (int i = 0; i < FINE_NODES; i++)
        v3_axpy(centre, 1.0 / FINE_NODES, &rec[FINE]->position[3 * i]);
    int drawn = 1;
    for (int k = 0; k < KINDS; k++) drawn &= (img[k] = draw(rec[k], centre)) != NULL;
    if (check(drawn, "the four pictures drawn")) {
        double p[KINDS];
        for (int k = 0; k < FINE; k++) p[k] = psnr(img[k], img[FINE]);
        printf("PSNR against the fine grid (%d nodes): uniform %d nodes %.2f dB, graded %d "
               "nodes (segments 0.005 and 0.02 m) %.2f dB, uniform %d nodes (0.02 m) %.2f dB; "
               "uniform against graded %.2f dB; %d of %d pixels drawn\n",
               FINE_NODES, NODES, p[UNIFORM], NODES, p[GRADED], COARSE_NODES, p[COARSE],
               psnr(img[UNIFORM], img[GRADED]), drawn_pixels(img[FINE]), WIDTH * HEIGHT);
        check(drawn_pixels(img[FINE]) > WIDTH * HEIGHT / 20, "the helix covers %d pixels (> 5 %%)",
              drawn_pixels(img[FINE]));
        check(p[GRADED] >= 30.0,
              "the graded grid's picture against the fine grid's: PSNR %.2f dB (>= 30)", p[GRADED]);
        check(p[GRADED] >= p[COARSE] - 0.5,
              "the graded grid's picture at least as close to the fine grid's as the uniform "
              "grid's of its longest segment: %.2f dB against %.2f dB (at most 0.5 dB less)", p[GRADED], p[COARSE]);
        const char *dir = test_dir();
        char path[600], err[256];
        for (int k = 0; k < KINDS; k++) {
            snprintf(path, sizeof path, "%s/helix_%s.png", dir, names[k]);
            if (image_write_png(img[k], path, err, sizeof err)) printf("%s\n", err);
        }
    }
    for (int k = 0; k < KINDS; k++) {
        image_destroy(img[k]);
        rod_recording_destroy(rec[k]);
    }
}

/* A hairpin inside the refined interval: straight along x to s0 = 0.35 m,
 * a half turn of radius RHO about z (1.5 tube radii: the turn's own
 * segments face each other across its inside), straight back along -x. */
#define HAIRPIN_S0 0.35
#define HAIRPIN_RHO 0.015
static rod_recording *hairpin_recording(int nodes, int graded)
{
    rod_recording *rec = helix_recording(nodes, graded, 0.0);
    static const double q0[9] = {0, 0, 1, 1, 0, 0, 0, 1, 0};
    const double s1 = HAIRPIN_S0 + M_PI * HAIRPIN_RHO;
    for (int i = 0; i < nodes; i++) {
        const double s = rod_recording_arc(rec, i);
        const double theta = s < HAIRPIN_S0 ? 0.0 : s > s1 ? M_PI : (s - HAIRPIN_S0) / HAIRPIN_RHO;
        double *r = &rec->position[3 * i], turn[9];
        const double axis[3] = {0, 0, theta};
        m3_exp(turn, axis);
        m3_mul(&rec->frame[9 * i], turn, q0);
        if (s < HAIRPIN_S0) v3_set(r, s, 0, 0);
        else if (s > s1) v3_set(r, HAIRPIN_S0 - (s - s1), 2 * HAIRPIN_RHO, 0);
        else v3_set(r, HAIRPIN_S0 + HAIRPIN_RHO * sin(theta), HAIRPIN_RHO * (1 - cos(theta)), 0);
    }
    return rec;
}

/* The strands' shading (occlusion_shade) on a graded grid: a hairpin's
 * picture from the graded grid against the fine uniform grid's. Pairs of
 * segments nearer than pi r in arc are one strand and do not darken each
 * other; a skip counting segments of the uniform ds would let the turn's
 * own segments 0.015 .. 0.031 m apart darken its inside. */
static void test_hairpin_shading(void)
{
    rod_recording *rec[3] = {hairpin_recording(NODES, 1), hairpin_recording(NODES, 0),
                             hairpin_recording(FINE_NODES, 0)};
    const char *names[3] = {"graded", "uniform", "fine"};
    const double look_at[3] = {HAIRPIN_S0 - 0.01, HAIRPIN_RHO, 0}, view[3] = {0.0, -0.4, 1.0};
    image *img[3];
    int drawn = 1;
    for (int k = 0; k < 3; k++)
        drawn &= (img[k] = draw_view(rec[k], look_at, view, 0.2, RENDER_COLOR_SOLID)) != NULL;
    if (check(drawn, "the hairpin drawn from a graded, a uniform and a fine uniform grid")) {
        const double p = psnr(img[0], img[2]), pu = psnr(img[1], img[2]);
        printf("hairpin: PSNR against the fine grid (%d nodes): graded %d nodes %.2f dB, uniform "
               "%d nodes %.2f dB; %d pixels drawn\n", FINE_NODES, NODES, p, NODES, pu,
               drawn_pixels(img[2]));
        /* measured: 51.2 dB; the skip of the uniform ds, unfiltered, 45.3 dB */
        check(p >= 48.0, "the hairpin's picture, graded against fine uniform: PSNR %.2f dB "
              "(>= 48)", p);
        char path[600], err[256];
        for (int k = 0; k < 3; k++) {
            snprintf(path, sizeof path, "%s/hairpin_%s.png", test_dir(), names[k]);
            if (image_write_png(img[k], path, err, sizeof err)) printf("%s\n", err);
        }
    }
    for (int k = 0; k < 3; k++) {
        image_destroy(img[k]);
        rod_recording_destroy(rec[k]);
    }
}

#define GRADED_SCENE "[rod]\nlength = 1.0\ndiameter = 0.01\ndensity = 850\n" \
                     "youngs_modulus = 87.5e6\nshear_modulus = 31.25e6\nnodes = 81\n" \
                     "self_contact = no\nrefine = 0.3 0.5 4\ndirection = 1 0 0\n" \
                     "[loads]\ngravity = 0 0 -9.81\n[solver]\nduration = 0.2\n"

static void test_library(void)
{
    rodsim_scene *sc = NULL;
    const rodsim_status st = rodsim_load_text("graded", GRADED_SCENE, NULL, 0, &sc);
    if (!check(st == RODSIM_OK && sc, "the library loads a graded scene (%s)",
               st == RODSIM_OK ? "ok" : rodsim_last_error(NULL)))
        return;
    check(rodsim_step(sc, 0.05) == RODSIM_OK, "it steps 0.05 s (%s)", rodsim_last_error(sc));
    rod_model m;
    char err[1024] = "";
    double arc[NODES];
    if (check(read_scene_text(GRADED_SCENE, &m, err, sizeof err) == 0, "the model reads (%s)",
              err) &&
        check(rodsim_nodes(sc) == NODES &&
              rodsim_node_arc(sc, 0, arc, NODES) == RODSIM_OK, "rodsim_node_arc: %d nodes",
              rodsim_nodes(sc))) {
        double worst = 0.0, formula = 0.0;
        int at = 0;
        for (int i = 0; i < NODES; i++) {
            worst = fmax(worst, fabs(arc[i] - rod_node_arc(&m, i)));
            if (fabs(arc[i] - graded_arc(i, NODES)) >= formula)
                formula = fabs(arc[i] - graded_arc(i, NODES)), at = i;
        }
        check(worst == 0.0, "rodsim_node_arc equals rod_node_arc at every node (largest "
              "difference %.3e m)", worst);
        check_abs("rodsim_node_arc against the grid's formula at its farthest node (m)", arc[at],
                  graded_arc(at, NODES), 1e-12);
        check_rel("the arc of node 40 (m): graded, not 40 L / 80 = 0.5", arc[40],
                  graded_arc(40, NODES), 1e-12);
        check(rodsim_node_arc(sc, 0, arc, NODES - 1) == RODSIM_BAD_INPUT &&
              strstr(rodsim_last_error(sc), "81 doubles"),
              "too small an array is refused: %s", rodsim_last_error(sc));
        rod_model_release(&m);
    }
    rodsim_free(sc);
}

static void test_run_video(void)
{
    const char *dir = test_dir();
    char out_dir[512], scene[512];
    static char output[1 << 16];
    snprintf(out_dir, sizeof out_dir, "%s/out", dir);
    snprintf(scene, sizeof scene, "%s/graded.ini", dir);
    test_write_in(dir, "graded.ini", GRADED_SCENE "[render]\ncolor = curvature\nwidth = 320\n"
                  "height = 180\n");
    const char *args[] = {"run", scene, "-o", out_dir, NULL};
    const int status = test_run_rodsim(args, output, sizeof output);
    char video[600];
    snprintf(video, sizeof video, "%s/graded.mp4", out_dir);
    FILE *f = fopen(video, "rb");
    check(status == 0 && f, "rodsim run draws a graded scene's video: exit %d (0), %s %s", status,
          video, f ? "written" : "missing");
    if (f) fclose(f);
    if (status != 0) printf("%s\n", output);
}

int main(void)
{
    test_stripe_phase();
    test_curvature_colour();
    test_frames_agree();
    test_hairpin_shading();
    test_library();
    test_run_video();
    return test_finish();
}
