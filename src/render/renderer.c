/* renderer.c: one view's renderer (renderer.h). */
#include "render/renderer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/clocks.h"
#include "base/vec3.h"
#include "render/color.h"
#include "render/geometry.h"
#include "render/instrument_mesh.h"
#include "render/shot.h"
#include "render/surface.h"

/* pixels; measured with 4x MSAA: less area to clear and resolve than 64
 * (llvmpipe's tile), and fewer boxes (GL calls) than 16 */
#define TILE 32
/* a tile's marks: something is drawn in it; a shadow may fall in it */
#define TILE_DRAWN 1
#define TILE_SHADOW 2
/* grid lines a direction at most, the camera following (drawn every frame,
 * multisampled over the whole picture: about 0.1 ms each at 720p) */
#define FOLLOW_GRID_LINES 40

/* Pixels per metre at a point (perspective: at its depth). */
static double pixels_per_metre(const render_camera *cam, const double p[3])
{
    if (cam->orthographic) return 1.0 / cam->metres_per_pixel;
    double to_eye[3];
    v3_sub(to_eye, cam->eye, p);
    return cam->height / (2 * v3_dot(to_eye, cam->direction) * camera_tan_half_fov(cam));
}

/* Marks the tiles under the screen box of the points (padded by pad, m). */
static void mark_points(renderer *r, const double *points, int count, double pad)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < count; i++) {
        double pixel[2];
        if (render_project(&r->camera, &points[3 * i], pixel)) {
            /* behind the camera: cannot bound it, draw everything */
            lo[0] = lo[1] = -INFINITY;
            hi[0] = hi[1] = INFINITY;
            break;
        }
        double reach = pad * pixels_per_metre(&r->camera, &points[3 * i]) + 3;
        lo[0] = fmin(lo[0], pixel[0] - reach);
        hi[0] = fmax(hi[0], pixel[0] + reach);
        lo[1] = fmin(lo[1], pixel[1] - reach);
        hi[1] = fmax(hi[1], pixel[1] + reach);
    }
    int height = r->camera.height;
    /* tiles count from the bottom row of pixels (GL's origin), TILE pixels square */
    int tx0 = (int)fmax(0, floor(lo[0] / TILE)), tx1 = (int)fmin(r->tiles_x - 1, floor(hi[0] / TILE));
    int ty0 = (int)fmax(0, floor((height - hi[1]) / TILE));
    int ty1 = (int)fmin(r->tiles_y - 1, floor((height - lo[1]) / TILE));
    for (int ty = ty0; ty <= ty1; ty++)
        for (int tx = tx0; tx <= tx1; tx++)
            r->tile_marked[ty * r->tiles_x + tx] |= (unsigned char)r->marking;
}

/* Marks the tiles where the shadow of the points (a polyline when chain,
 * else a hull: every pair), padded by pad (m), can fall on a receiver: the
 * shadow volume of each segment (the segment swept away from the light)
 * clipped to each receiver's catcher. */
static void mark_shadow(renderer *r, const double *points, int count, int chain, double pad)
{
    const shadow_scene *sh = &r->shadow;
    double reach = SHADOW_REACH * sh->size, hull[3 * 16 * 64];
    r->marking = TILE_SHADOW;
    for (int c = 0; c < sh->catcher_count; c++) {
        int kept = 0;
        for (int i = 0; i < count; i++)
            for (int j = chain ? i + 1 : i; j < (chain ? (i + 2 < count ? i + 2 : count) : count); j++) {
                const double *a = &points[3 * i], *b = &points[3 * j];
                double poly[3 * 16];
                v3_copy(&poly[0], a);
                v3_copy(&poly[3], b);
                v3_copy(&poly[6], b);
                v3_axpy(&poly[6], -reach, sh->key);
                v3_copy(&poly[9], a);
                v3_axpy(&poly[9], -reach, sh->key);
                int left = shadow_clip_polygon(poly, 4, &sh->catchers[c]);
                if (left == 0) continue;
                if (chain) {
                    mark_points(r, poly, left, pad * sh->catchers[c].stretch + sh->shadow_pad);
                    continue;
                }
                for (int q = 0; q < left && kept < 16 * 64; q++) v3_copy(&hull[3 * kept++], &poly[3 * q]);
            }
        if (kept > 0) mark_points(r, hull, kept, pad * sh->catchers[c].stretch + sh->shadow_pad);
    }
    r->marking = TILE_DRAWN;
}

/* The runs of tiles in each tile row with one of the bits `bits` marked,
 * as boxes into boxes; their count. */
static int tile_runs(const renderer *r, int bits, int (*boxes)[4])
{
    int count = 0, width = r->camera.width, height = r->camera.height;
    for (int ty = 0; ty < r->tiles_y; ty++)
        for (int tx = 0; tx < r->tiles_x; tx++) {
            if (!(r->tile_marked[ty * r->tiles_x + tx] & bits)) continue;
            int run = tx;
            while (run + 1 < r->tiles_x && r->tile_marked[ty * r->tiles_x + run + 1] & bits) run++;
            int gl_y0 = ty * TILE, gl_y1 = (ty + 1) * TILE < height ? (ty + 1) * TILE : height;
            int x1 = (run + 1) * TILE < width ? (run + 1) * TILE : width;
            int *box = boxes[count++];
            box[0] = tx * TILE;
            box[1] = height - gl_y1;
            box[2] = x1 - tx * TILE;
            box[3] = gl_y1 - gl_y0;
            tx = run;
        }
    return count;
}

/* The disjoint boxes that hold this frame's tube, stripe, end glyphs and arrows:
 * only they are cleared, drawn, resolved and read (the multisample resolve
 * is llvmpipe's main cost), the rest of the picture is the backdrop. */
static void frame_boxes(renderer *r, const rod_recording *rec, int frame,
                        const rod_recording *given, int given_frame)
{
    if (r->follow) {
        /* the camera moves: everything changes, the picture is one box drawn whole */
        r->box_count = 1;
        r->boxes[0][0] = r->boxes[0][1] = 0;
        r->boxes[0][2] = r->camera.width;
        r->boxes[0][3] = r->camera.height;
        memcpy(r->drawn_boxes[0], r->boxes[0], sizeof r->boxes[0]);
        r->drawn_box_count = 1;
        return;
    }
    memset(r->tile_marked, 0, (size_t)r->tiles_x * (size_t)r->tiles_y);
    r->marking = TILE_DRAWN;
    for (int k = 0; k + 1 < rec->nodes; k++)
        mark_points(r, node_position(rec, frame, k), 2, r->pad);
    for (int end = 0; end < 2; end++) {
        double glyph[3 * GLYPH_MAX_POINTS], pad;
        int chain, count = glyph_points(rec, r->o, r->radius, frame, end, glyph, &pad, &chain);
        if (chain)
            for (int k = 0; k + 1 < count; k++) mark_points(r, &glyph[3 * k], 2, pad);
        else if (count > 0)
            mark_points(r, glyph, count, pad);
    }
    for (int k = 0; k < given->instrument_count; k++) {
        double points[3 * INSTRUMENT_MESH_POINTS], pad;
        if (!instrument_mesh_points(given, given_frame, k, 2.0 * r->radius, points, &pad)) continue;
        for (int side = 0; side < 2; side++) {
            const double *p = &points[3 * 8 * side];
            mark_points(r, p, 2, pad);
            mark_points(r, p + 6, 2, pad);
            mark_points(r, p + 12, 4, pad);
            if (r->shadow.shadows) {
                mark_shadow(r, p, 2, 1, pad);
                mark_shadow(r, p + 6, 2, 1, pad);
                mark_shadow(r, p + 12, 4, 0, pad);
            }
        }
    }
    for (int which = 0; r->o->arrows && which < 2; which++) {
        double ends[6], d[3], length;
        if (!arrow_geometry(&r->arrows, rec, frame, which, ends, d, &length)) continue;
        v3_copy(&ends[3], ends);
        v3_axpy(&ends[3], length, d);
        mark_points(r, ends, 2, r->arrows.style.head_radius);
        if (r->shadow.shadows) mark_shadow(r, ends, 2, 1, r->arrows.style.head_radius);
    }
    for (int k = 0; k < given->surface_count; k++) {
        /* an elastic pad, drawn deformed each frame: the box around it */
        const double *pad = rod_recording_pad_positions(given, k, given_frame);
        if (pad) mark_points(r, pad, given->surfaces[k].pad_node_count, 0);
    }
    const double *punctures;
    int puncture_count = rod_recording_punctures(given, given_frame, &punctures);
    for (int i = 0; r->shadow.receivers && i < puncture_count; i++)
        mark_points(r, &punctures[3 * i], 1, 2 * r->radius + r->shadow.lift);
    if (r->shadow.shadows) {
        for (int k = 0; k + 1 < rec->nodes; k++)
            mark_shadow(r, node_position(rec, frame, k), 2, 1, r->pad);
        for (int end = 0; end < 2; end++) {
            double glyph[3 * GLYPH_MAX_POINTS], pad;
            int chain, count = glyph_points(rec, r->o, r->radius, frame, end, glyph, &pad, &chain);
            if (count > 0) mark_shadow(r, glyph, count, chain, pad);
        }
    }
    /* runs of marked tiles in each tile row become boxes */
    r->box_count = tile_runs(r, TILE_DRAWN | TILE_SHADOW, r->boxes);
    r->drawn_box_count = tile_runs(r, TILE_DRAWN, r->drawn_boxes);
}

void renderer_destroy(renderer *r)
{
    gl_renderer_destroy(r->gl);
    image_destroy(r->backdrop);
    free(r->tile_marked);
    free(r->boxes);
    free(r->drawn_boxes);
    overlay_destroy(&r->overlay);
    follow_destroy(r->follow);
    free(r->mesh.vertices);
    free(r->mesh.indices);
    free(r->grid.lines);
    for (int k = 0; k < r->pad_slots; k++) surface_mesh_topology_release(&r->pads[k]);
    free(r->pads);
    rod_recording_destroy(r->view);
    free(r->values);
    free(r->colors);
    free(r->previous);
    occlusion_destroy(&r->shading);
    free(r->line.point);
    free(r->line.frame);
    free(r->line.t);
    free(r->line.node);
    free(r->line.first);
    free(r->line.phi);
    edge_aa_destroy(r->edge_aa);
    cutaway_scratch_destroy(r->cut_scratch);
}

void renderer_remember(renderer *r, const rod_recording *rec, int frame)
{
    if (!r->previous) return;
    memcpy(r->previous, node_position(rec, frame, 0), (size_t)rec->nodes * 3 * sizeof(double));
    r->previous_time = rec->time[frame];
    r->have_previous = 1;
}

/* The buffers a frame is drawn with: the centreline's rings, the mesh, the
 * strands' shading, the grid's lines, and the colours' or the magnified
 * frame's scratch. 0, or -1 when out of memory. */
static int renderer_buffers(renderer *r, const rod_recording *rec, const render_options *o)
{
    if (o->magnify != 1) r->view = recording_like(rec, 2);
    if (o->color != RENDER_COLOR_SOLID) {
        r->values = malloc((size_t)rec->nodes * sizeof(double));
        r->colors = malloc((size_t)rec->nodes * 3 * sizeof(float));
        r->previous = malloc((size_t)rec->nodes * 3 * sizeof(double));
    }
    int sides = o->sides;
    /* the drawn centreline's rings: one per node, or up to SMOOTH_MOST_RINGS
     * per segment (centreline_rings) */
    const int rings = o->smooth ? (rec->nodes - 1) * SMOOTH_MOST_RINGS + 1 : rec->nodes;
    r->line.capacity = rings;
    r->line.point = malloc((size_t)rings * 3 * sizeof(double));
    r->line.frame = malloc((size_t)rings * 9 * sizeof(double));
    r->line.t = malloc((size_t)rings * sizeof(double));
    r->line.node = malloc((size_t)rings * sizeof(int));
    r->line.first = malloc((size_t)rec->nodes * sizeof(int));
    r->line.phi = malloc((size_t)rec->nodes * sizeof(double));
    r->mesh.max_vertices = rings * (sides + 3) + 2 * (sides + 1) + 2 * GLYPH_VERTICES +
                           2 * ARROW_MAX_VERTICES + PUNCTURE_VERTICES +
                           rec->instrument_count * INSTRUMENT_MESH_VERTICES;
    r->mesh.max_indices = 6 * rings * (sides + 2) + 6 * sides + 2 * GLYPH_INDICES +
                          2 * ARROW_MAX_INDICES + PUNCTURE_INDICES +
                          rec->instrument_count * INSTRUMENT_MESH_INDICES;
    for (int k = 0; rec->surfaces && k < rec->surface_count; k++) {
        /* an elastic pad's surface, drawn each frame: three vertices a triangle */
        const int triangles = rec->surfaces[k].pad_triangle_count;
        r->mesh.max_vertices += 3 * triangles;
        r->mesh.max_indices += 3 * triangles;
        if (o->cutaway) {
            /* cut open: its cap and its cut triangles' pieces */
            r->mesh.max_vertices += CUTAWAY_EXTRA_VERTICES(triangles);
            r->mesh.max_indices += CUTAWAY_EXTRA_INDICES(triangles);
        }
    }
    if (o->cutaway) {
        /* the punctures' discs cut too */
        r->mesh.max_vertices += CUTAWAY_EXTRA_VERTICES(PUNCTURE_INDICES / 3);
        r->mesh.max_indices += CUTAWAY_EXTRA_INDICES(PUNCTURE_INDICES / 3);
        r->cut_scratch = cutaway_scratch_create();
    }
    int shading = occlusion_create(&r->shading, rec->nodes, rings, sides, r->radius,
                                   rod_recording_longest_segment(rec));
    r->mesh.vertices = malloc((size_t)r->mesh.max_vertices * sizeof(render_vertex));
    r->mesh.indices = malloc((size_t)r->mesh.max_indices * sizeof(unsigned));
    r->grid.capacity = o->grid ? 4 * (GRID_MAX_LINES + 2) : 0;
    r->grid.lines = malloc((size_t)(r->grid.capacity + 1) * sizeof(render_vertex));
    return shading || !r->mesh.vertices || !r->mesh.indices || !r->grid.lines ||
                   !r->line.point || !r->line.frame || !r->line.t || !r->line.node ||
                   !r->line.first || !r->line.phi || (o->magnify != 1 && !r->view) ||
                   (o->color != RENDER_COLOR_SOLID && (!r->values || !r->colors || !r->previous)) ||
                   (o->cutaway && !r->cut_scratch)
               ? -1
               : 0;
}

/* The grid's cells for a camera that follows: sized for the widest picture
 * followed, one spacing for the whole video. */
static void renderer_follow_grid(renderer *r, const rod_recording *shown, const render_options *o,
                                 int floor)
{
    /* the grid's cells sized for the widest picture followed (the run's
     * camera shows its motion across about 0.7 of the height), not for
     * the whole path */
    double largest = 0;
    for (int f = 0; f < r->follow->count; f++)
        largest = fmax(largest, r->follow->extent[f]);
    largest *= r->camera.orthographic ? 2 : 2 * tan(0.5 * PERSPECTIVE_FOVY);
    r->grid.size = fmax(fmin(r->grid.size, 0.7 * largest), 0.1 * shown->length);
    if (o->grid && !floor) {
        /* one spacing for the video (a grid whose cells jump would read as
         * motion), coarse enough that the widest region seen has at most
         * FOLLOW_GRID_LINES lines a direction: they are drawn every frame */
        double widest = 0;
        for (int f = 0; f < r->follow->count; f++) {
            render_camera cam;
            double lo[2], hi[2];
            follow_camera(r->follow, shown, o, &r->arrows, f, r->follow->time[f], &cam);
            grid_region(&r->grid, &cam, lo, hi);
            widest = fmax(widest, fmax(hi[0] - lo[0], hi[1] - lo[1]));
        }
        double spacing = nice_below(r->grid.size / 6);
        while (widest / spacing > FOLLOW_GRID_LINES) spacing = nice_below(spacing * 2.01);
        r->grid.fixed_spacing = spacing;
    }
}

/* The backdrop grid and, framing follow or knot, the camera's path, over
 * the motion as drawn (shown); floor: a floor is drawn. 0, or -1 when out
 * of memory. */
static int renderer_framing(renderer *r, const rod_recording *shown, const render_options *o,
                            const frame_band *band, int floor)
{
    if (o->grid && !floor) grid_build(&r->grid, shown, &r->camera, r->radius, o->background);
    r->fitted = r->camera;
    if (o->framing == RENDER_FRAMING_RUN && !o->directed) return 0;
    r->follow = follow_create(shown, o, &r->arrows, r->radius, &r->camera, band,
                              floor || shown->surface_count > 0 ||
                                  v3_norm(shown->distributed_force) > 0);
    if (!r->follow) return -1;
    /* a directed camera without a framing path: each camera's own grid spacing */
    if (o->framing != RENDER_FRAMING_RUN) renderer_follow_grid(r, shown, o, floor);
    return 0;
}

/* The overlay, the GL target with the grid's lines, and the receivers
 * with the shadow map. 0, or -1 with a message. */
static int renderer_gl(renderer *r, const rod_recording *rec, const render_options *o,
                       const char *scene_name, const receiver_plan *plan, char *err,
                       size_t errlen)
{
    if (overlay_create(&r->overlay, rec, o, scene_name, r->radius, &r->arrows, &r->camera,
                       o->overlay, err, errlen))
        return -1;
    r->gl = gl_renderer_create(o->width, o->height, o->samples, r->mesh.max_vertices,
                               r->mesh.max_indices, r->grid.capacity, err, errlen);
    if (!r->gl) return -1;
    if (o->grid) gl_renderer_set_lines(r->gl, r->grid.lines, r->grid.count);
    if (r->follow) gl_renderer_set_whole_boxes(r->gl, 1, o->background);
    /* the cut face is a section through the tissue, where no light falls:
     * shaded, never shadowed (the key light's map, grazing it, drew its
     * texels there as steps) */
    if (r->cut.on) gl_renderer_set_unshadowed(r->gl, r->cut.normal);
    r->pad = STRIPE_LIFT * r->radius;
    return shadow_receivers(&r->shadow, r->gl, plan, rec, o, &r->camera, err, errlen);
}

/* The tile grid, the backdrop drawn once and, antialias fxaa, the edges'
 * smoothing. 0, or -1 with a message. */
static int renderer_backdrop(renderer *r, const render_options *o, char *err, size_t errlen)
{
    r->tiles_x = (o->width + TILE - 1) / TILE;
    r->tiles_y = (o->height + TILE - 1) / TILE;
    r->tile_marked = malloc((size_t)r->tiles_x * (size_t)r->tiles_y);
    r->boxes = malloc((size_t)r->tiles_x * (size_t)r->tiles_y * sizeof *r->boxes);
    r->drawn_boxes = malloc((size_t)r->tiles_x * (size_t)r->tiles_y * sizeof *r->drawn_boxes);
    r->backdrop = image_create(o->width, o->height);
    if (!r->tile_marked || !r->boxes || !r->drawn_boxes) {
        snprintf(err, errlen, "render: out of memory");
        return -1;
    }
    if (!r->backdrop || gl_renderer_draw_backdrop(r->gl, &r->camera, o->background, r->backdrop)) {
        snprintf(err, errlen, "render: cannot draw the backdrop (out of memory or OpenGL error)");
        return -1;
    }
    if (o->antialias == RENDER_AA_FXAA && o->samples > 0) {
        /* the backdrop (thin grid lines) stays multisampled: it is drawn once */
        r->edge_aa = edge_aa_create(r->backdrop, r->tiles_x * r->tiles_y);
        if (!r->edge_aa) {
            snprintf(err, errlen, "render: out of memory");
            return -1;
        }
        if (gl_renderer_set_samples(r->gl, 0, err, errlen)) return -1;
    }
    return 0;
}

int renderer_create(renderer *r, const rod_recording *rec, const render_options *o,
                    const char *scene_name, const frame_band *band, char *err, size_t errlen)
{
    memset(r, 0, sizeof *r);
    r->rec = rec;
    r->o = o;
    r->band = *band;
    r->radius = render_visual_radius(rec, o);
    /* the camera and the grid frame the motion as drawn (magnified) */
    rod_recording *shown = o->magnify != 1 ? magnified_copy(rec, o->magnify) : NULL;
    camera_fit(&r->camera, shown ? shown : rec, o, band);
    cutaway_resolve(&r->cut, rec, o);
    arrow_scales_compute(&r->arrows, rec, r->radius, o->arrows);
    if (renderer_buffers(r, rec, o) || (o->magnify != 1 && !shown)) {
        snprintf(err, errlen, "render: out of memory");
        rod_recording_destroy(shown);
        renderer_destroy(r);
        return -1;
    }
    const rod_recording *drawn = shown ? shown : rec;
    receiver_plan plan;
    receiver_plan_make(&plan, drawn, o, r->radius);
    plan.cut = r->cut;
    /* Decision: a floor (a plane surface or the ground) replaces the backdrop
     * grid, which would float over it or cut through it; the scale bar stays. */
    int floor = plan.ground;
    for (int k = 0; rec->surfaces && k < rec->surface_count; k++)
        floor |= rec->surfaces[k].shape == RECORDING_SURFACE_PLANE;
    const int framed = renderer_framing(r, drawn, o, band, floor);
    rod_recording_destroy(shown);
    if (framed) {
        snprintf(err, errlen, "render: out of memory");
        renderer_destroy(r);
        return -1;
    }
    if (renderer_gl(r, rec, o, scene_name, &plan, err, errlen) ||
        renderer_backdrop(r, o, err, errlen)) {
        renderer_destroy(r);
        return -1;
    }
    return 0;
}

/* What a directed camera starts from at time t: the framing's camera of the
 * frame being drawn, and the knot's centre. */
typedef struct directed_base {
    renderer *r;
    const rod_recording *drawn;
    int frame;
} directed_base;

static void directed_base_at(void *context, double t, render_camera *base, double knot[3],
                             int *has_knot)
{
    const directed_base *b = context;
    renderer *r = b->r;
    if (r->o->framing != RENDER_FRAMING_RUN)
        follow_camera(r->follow, b->drawn, r->o, &r->arrows, b->frame, t, base);
    else
        *base = r->fitted;
    *has_knot = follow_knot_centre(r->follow, t, knot) == 0;
}

/* Follow framing or a directed camera: this frame's camera, and what hangs
 * on it (the grid, the scale bar; the backdrop is not used: the whole
 * picture is one box). */
static void renderer_follow(renderer *r, const rod_recording *drawn, int drawn_frame, double t)
{
    if (r->o->directed) {
        directed_base base = {r, drawn, drawn_frame};
        render_directed_camera(r->o, t, directed_base_at, &base, r->follow->size, &r->camera);
    } else {
        follow_camera(r->follow, drawn, r->o, &r->arrows, drawn_frame, t, &r->camera);
    }
    if (r->shadow.shadows) {
        /* the rod of this frame, with its glyphs' reach, as its own receiver */
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int k = 0; k < drawn->nodes; k++) {
            const double *q = node_position(drawn, drawn_frame, k);
            for (int c = 0; c < 3; c++) lo[c] = fmin(lo[c], q[c]), hi[c] = fmax(hi[c], q[c]);
        }
        for (int end = 0; end < 2; end++) {
            double glyph[3 * GLYPH_MAX_POINTS], pad;
            int chain, count = glyph_points(drawn, r->o, r->radius, drawn_frame, end, glyph, &pad,
                                            &chain);
            for (int i = 0; i < count; i++)
                for (int c = 0; c < 3; c++) {
                    lo[c] = fmin(lo[c], glyph[3 * i + c] - pad);
                    hi[c] = fmax(hi[c], glyph[3 * i + c] + pad);
                }
        }
        const double reach = 2 * r->radius + r->pad;
        for (int c = 0; c < 3; c++) lo[c] -= reach, hi[c] += reach;
        char err[256];
        /* uniforms only: the map is made */
        (void)shadow_fit(&r->shadow, r->gl, &r->camera, r->radius, lo, hi, err, sizeof err);
    }
    if (r->o->grid && r->grid.count > 0) {
        grid_lines(&r->grid, &r->camera);
        gl_renderer_set_lines(r->gl, r->grid.lines, r->grid.count);
    }
    if (r->o->grid) overlay_scale_bar(&r->overlay, r->o->width, r->camera.metres_per_pixel);
}

/* The colour of each node of frame `frame` (the true motion's). */
static void renderer_colors(renderer *r, const rod_recording *rec, int frame)
{
    color_values(rec, frame, r->o->color, r->have_previous ? r->previous : NULL,
                 r->previous_time, r->values);
    double span = r->overlay.color_hi - r->overlay.color_lo;
    for (int k = 0; k < rec->nodes; k++) {
        unsigned char rgb[3];
        render_colormap_rgb(r->o->colormap, (r->values[k] - r->overlay.color_lo) / span, rgb);
        for (int c = 0; c < 3; c++) r->colors[3 * k + c] = rgb[c] / 255.0f;
    }
    renderer_remember(r, rec, frame);
}

/* Each elastic pad's surface as it is at given_frame (smooth-shaded, the
 * skin's colour): it is drawn every frame, not in the backdrop, and casts
 * no shadow. */
static void renderer_pads(renderer *r, const rod_recording *given, int given_frame)
{
    if (!r->pads) {
        r->pads = calloc((size_t)given->surface_count + 1, sizeof *r->pads);
        if (!r->pads) return; /* out of memory: the pads are left out */
        r->pad_slots = given->surface_count;
        for (int k = 0; k < given->surface_count; k++) {
            const recording_surface *sf = &given->surfaces[k];
            recording_surface shape = {0};
            shape.mesh_vertex_count = sf->pad_node_count;
            shape.mesh_triangle_count = sf->pad_triangle_count;
            shape.mesh_triangles = sf->pad_triangles;
            if (sf->pad_triangles) (void)surface_mesh_topology_init(&r->pads[k], &shape);
        }
    }
    for (int k = 0; k < given->surface_count && k < r->pad_slots; k++) {
        const recording_surface *sf = &given->surfaces[k];
        const double *pad = rod_recording_pad_positions(given, k, given_frame);
        if (!pad) continue;
        recording_surface now = {0};
        now.shape = RECORDING_SURFACE_MESH;
        now.mesh_vertex_count = sf->pad_node_count;
        now.mesh_triangle_count = sf->pad_triangle_count;
        now.mesh_vertices = (double *)pad;
        now.mesh_triangles = sf->pad_triangles;
        if (r->pads[k].triangles != sf->pad_triangle_count) continue; /* out of memory */
        const int first = r->mesh.index_count;
        surface_add_mesh_shaded(&r->mesh, &now, &r->pads[k],
                                sf->tissue ? render_skin_color : render_surface_color);
        if (r->cut.on && sf->tissue) {
            /* the dermis as thick as the pad at rest (its box) allows */
            double lo[3], hi[3];
            surface_bounds(sf, lo, hi);
            cutaway_cut(&r->mesh, first, &r->cut, cutaway_dermis(lo, hi), r->cut_scratch);
        }
    }
}

/* The colours of the rods of a scene of several, after the first's
 * (the [render] rod_color): orange, green, red, purple, teal, gold, grey */
static const float rod_palette[RECORDING_MAX_RODS - 1][3] = {
    {0.85f, 0.51f, 0.17f}, {0.23f, 0.60f, 0.29f}, {0.75f, 0.22f, 0.17f}, {0.56f, 0.27f, 0.68f},
    {0.09f, 0.63f, 0.52f}, {0.79f, 0.64f, 0.15f}, {0.50f, 0.55f, 0.55f}};

/* Each rod of a recording of several (rec->rod_count > 1) as its own tube,
 * stripe and end glyphs, in its own colour: rod k's nodes of this frame
 * copied into a recording of one frame and one rod */
static void renderer_rods(renderer *r, const rod_recording *rec, int frame)
{
    render_mesh *m = &r->mesh;
    const size_t n = (size_t)rec->nodes;
    double *position = malloc(n * 3 * sizeof(double)), *frames = malloc(n * 9 * sizeof(double));
    double *twist = malloc(n * sizeof(double)), *tension = malloc(n * sizeof(double));
    int no_punctures = 0;
    for (int k = 0; position && frames && twist && tension && k < rec->rod_count; k++) {
        const size_t first = (size_t)rec->rod_first[k], count = (size_t)rec->rod_first[k + 1] - first;
        const size_t at = (size_t)frame * n + first;
        rod_recording view = *rec;
        memcpy(position, &rec->position[3 * at], count * 3 * sizeof(double));
        memcpy(frames, &rec->frame[9 * at], count * 9 * sizeof(double));
        memcpy(twist, &rec->twist[at], count * sizeof(double));
        memcpy(tension, &rec->tension[at], count * sizeof(double));
        view.nodes = (int)count;
        view.rod_count = 0;
        view.frame_count = view.capacity = 1;
        view.time = &rec->time[frame];
        view.position = position;
        view.frame = frames;
        view.twist = twist;
        view.tension = tension;
        view.tip_force = &rec->tip_force[3 * frame];
        view.tip_moment = &rec->tip_moment[3 * frame];
        view.puncture_count = &no_punctures;
        view.puncture = NULL;
        view.instrument_count = 0;
        view.instrument_pose = NULL;
        view.needle_radius = 0.0;
        view.ends[0] = rec->rod_end[k][0];
        view.ends[1] = rec->rod_end[k][1];
        view.arc = rec->arc ? &rec->arc[first] : NULL; /* borrowed: rod k's own arc */
        const float *solid = k == 0 ? r->o->rod_color : rod_palette[(k - 1) % (RECORDING_MAX_RODS - 1)];
        const float *colors = r->o->color != RENDER_COLOR_SOLID && r->colors ? r->colors + 3 * first : NULL;
        centreline_rings(&r->line, &view, 0, r->o->smooth);
        mesh_tube(m, &view, &r->line, 0, r->radius, r->o->sides, colors, solid);
        if (r->o->stripe != RENDER_STRIPE_OFF)
            mesh_stripe(m, &view, &r->line, 0, r->radius, r->o->stripe, color_stripe(r->o));
        glyph_add_ends(m, &view, r->o, 0, r->radius);
    }
    free(position);
    free(frames);
    free(twist);
    free(tension);
}

/* The frame's meshes (the tube, its stripe shaded by the strands near,
 * the glyphs, the arrows; then the punctures, which cast no shadow) and
 * the boxes of the picture they cover. rec, frame: the motion as drawn;
 * given, given_frame: as recorded. */
static void renderer_meshes(renderer *r, const rod_recording *rec, int frame,
                            const rod_recording *given, int given_frame)
{
    render_mesh *m = &r->mesh;
    if (rec->rod_count > 1) {
        renderer_rods(r, rec, frame);
        instrument_mesh_add(m, given, given_frame, 2.0 * r->radius); /* the scene's */
        if (r->o->arrows) glyph_add_arrows(m, &r->arrows, rec, frame);
        r->caster_indices = m->index_count;
        renderer_pads(r, given, given_frame); /* the pad the rods share */
        if (r->shadow.receivers)
            surface_add_punctures(m, given, given_frame, r->radius, r->shadow.lift);
        frame_boxes(r, rec, frame, given, given_frame);
        return;
    }
    unsigned tube = (unsigned)m->vertex_count;
    centreline_rings(&r->line, rec, frame, r->o->smooth);
    mesh_tube(m, rec, &r->line, frame, r->radius, r->o->sides, r->colors, r->o->rod_color);
    int stripe = r->o->stripe != RENDER_STRIPE_OFF ? m->vertex_count : -1;
    if (stripe >= 0)
        mesh_stripe(m, rec, &r->line, frame, r->radius, r->o->stripe, color_stripe(r->o));
    occlusion_shade(&r->shading, m, &r->line, rec, frame, r->o->sides, r->radius, tube, stripe);
    glyph_add_ends(m, rec, r->o, frame, r->radius);
    instrument_mesh_add(m, given, given_frame, 2.0 * r->radius);
    if (r->o->arrows) glyph_add_arrows(m, &r->arrows, rec, frame);
    r->caster_indices = m->index_count;
    renderer_pads(r, given, given_frame);
    const int discs = m->index_count;
    if (r->shadow.receivers)
        surface_add_punctures(m, given, given_frame, r->radius, r->shadow.lift);
    if (r->cut.on) cutaway_clip(m, discs, &r->cut);
    frame_boxes(r, rec, frame, given, given_frame);
}

/* out made the backdrop again. A tracked frame (image_track_changes) is
 * the backdrop but where it was written since: only those pixels are
 * copied (a 720p frame is 2.7 MB; the rod and the overlay cover a few %),
 * and its marks become this frame's boxes, where the composite, the
 * shadows and FXAA write; the overlay marks its own. */
static void restore_backdrop(const renderer *r, image *out)
{
    if (!out->changed) {
        memcpy(out->rgb, r->backdrop->rgb, (size_t)out->width * (size_t)out->height * 3);
        return;
    }
    for (int y = 0; y < out->height; y++) {
        const int lo = out->changed[2 * y], hi = out->changed[2 * y + 1];
        if (lo >= hi) continue;
        const size_t at = ((size_t)y * (size_t)out->width + (size_t)lo) * 3;
        memcpy(out->rgb + at, r->backdrop->rgb + at, (size_t)(hi - lo) * 3);
    }
    image_changes_reset(out);
    for (int b = 0; b < r->box_count; b++) {
        const int *box = r->boxes[b];
        image_mark(out, box[0], box[1], box[0] + box[2], box[1] + box[3]);
    }
}

/* The drawn boxes (premultiplied RGBA read back in read_box, rows
 * bottom-up) over the backdrop into out. */
static void renderer_composite(const renderer *r, const unsigned char *rgba, const int read_box[4],
                               image *out)
{
    /* premultiplied rod over the backdrop: out = C + (1 - alpha) B, inside the boxes only
     * (the read rectangle outside them holds stale pixels) */
    int(*boxes)[4] = r->boxes;
    int box_count = r->box_count;
    if (r->follow) {
        /* one opaque box, the whole picture: its pixels as they are */
        image_mark(out, 0, 0, out->width, out->height);
        for (int y = 0; y < out->height; y++) {
            const unsigned char *src = rgba + (size_t)(out->height - 1 - y) * (size_t)out->width * 4;
            unsigned char *dst = out->rgb + (size_t)y * (size_t)out->width * 3;
            for (int x = 0; x < out->width; x++, src += 4, dst += 3) {
                dst[0] = src[0];
                dst[1] = src[1];
                dst[2] = src[2];
            }
        }
    } else {
        restore_backdrop(r, out);
        /* boxes from the receivers' cache: the shadows darken the backdrop,
         * the GL drew only where something is drawn */
        if (gl_renderer_darken(r->gl, &r->boxes[0][0], r->box_count, out)) {
            boxes = r->drawn_boxes;
            box_count = r->drawn_box_count;
        }
    }
    for (int b = 0; !r->follow && b < box_count; b++) {
        const int *box = boxes[b];
        for (int y = box[1]; y < box[1] + box[3]; y++) {
            int row = read_box[1] + read_box[3] - 1 - y; /* GL rows run bottom-up */
            const unsigned char *src =
                rgba + ((size_t)row * (size_t)read_box[2] + (size_t)(box[0] - read_box[0])) * 4;
            unsigned char *dst = out->rgb + ((size_t)y * (size_t)out->width + (size_t)box[0]) * 3;
            for (int x = 0; x < box[2]; x++, src += 4, dst += 3) {
                unsigned keep = 255u - src[3];
                if (keep == 255) continue;
                for (int c = 0; c < 3; c++) {
                    unsigned v = src[c] + (dst[c] * keep + 127) / 255;
                    dst[c] = (unsigned char)(v > 255 ? 255 : v);
                }
            }
        }
    }
}

int renderer_draw(renderer *r, const rod_recording *rec, int frame, image *out)
{
    render_timing *timing = r->o->timing;
    double t0 = timing ? wall_seconds() : 0;
    render_mesh *m = &r->mesh;
    m->vertex_count = m->index_count = 0;
    /* the colours come from the true motion, the shapes from the drawn (magnified) one */
    if (r->colors) renderer_colors(r, rec, frame);
    const rod_recording *given = rec, *drawn = rec;
    int given_frame = frame, drawn_frame = frame;
    if (r->view) {
        magnify_frame(rec, 0, 1, r->view, 0);
        magnify_frame(rec, frame, r->o->magnify, r->view, 1);
        drawn = r->view;
        drawn_frame = 1;
    }
    if (r->follow) renderer_follow(r, drawn, drawn_frame, given->time[given_frame]);
    renderer_meshes(r, drawn, drawn_frame, given, given_frame);
    double t1 = timing ? wall_seconds() : 0;
    int read_box[4];
    const unsigned char *rgba = gl_renderer_draw_boxes(
        r->gl, &r->camera, m->vertices, m->vertex_count, m->indices, m->index_count,
        r->caster_indices, &r->boxes[0][0], r->box_count, &r->drawn_boxes[0][0], r->drawn_box_count,
        read_box, timing ? &timing->shadow : NULL);
    if (!rgba) return -1;
    double t2 = timing ? wall_seconds() : 0;
    renderer_composite(r, rgba, read_box, out);
    /* before the text, which FreeType draws antialiased (framing follow: one
     * box, the whole picture) */
    if (r->edge_aa) edge_aa_frame(r->edge_aa, out, (const int(*)[4])r->boxes, r->box_count);
    double t3 = timing ? wall_seconds() : 0;
    if (r->o->overlay && r->draws_overlay) {
        overlay_knot(&r->overlay, given, given_frame);
        overlay_draw(out, &r->overlay, drawn, r->o, &r->camera, drawn_frame);
    }
    if (timing) {
        double t4 = wall_seconds();
        timing->mesh += t1 - t0;
        timing->gl += t2 - t1;
        timing->composite += t3 - t2;
        timing->overlay += t4 - t3;
    }
    return 0;
}
