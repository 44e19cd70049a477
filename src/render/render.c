/* render.c: the frame loop (see render.h): a run's frames drawn one by one
 * by one renderer, or by one per view side by side (a split frame), handed
 * to a writer thread that encodes the video and writes the PNG frames while
 * the next frame is drawn; the poster and every file committed together. */
#include "render/render.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/clocks.h"
#include "base/outfile.h"
#include "render/renderer.h"
#include "render/video.h"

#define QUEUE_SLOTS 3

/* Frames handed from the drawing thread (GL) to the writing thread
 * (encoder, PNG): drawing frame k+1 overlaps encoding frame k. */
typedef struct frame_queue {
    pthread_mutex_t lock;
    pthread_cond_t changed;
    image *slots[QUEUE_SLOTS];
    int produced, consumed; /* frames handed over, frames written */
    int done;               /* no more frames will come */
    int failed;             /* the writer failed: message in err */
    char err[768];
    video_writer *video;    /* NULL: no video */
    const char *frames_dir; /* NULL: no PNG frames */
    render_timing *timing;  /* NULL: not measured; the writer adds png only */
} frame_queue;

static void *writer_thread(void *arg)
{
    frame_queue *q = arg;
    for (;;) {
        pthread_mutex_lock(&q->lock);
        while (q->consumed == q->produced && !q->done) pthread_cond_wait(&q->changed, &q->lock);
        if (q->consumed == q->produced) {
            pthread_mutex_unlock(&q->lock);
            return NULL;
        }
        int index = q->consumed;
        pthread_mutex_unlock(&q->lock);

        const image *frame = q->slots[index % QUEUE_SLOTS];
        char err[768] = "";
        int status = 0;
        if (q->video) status = video_writer_add(q->video, frame, err, sizeof err);
        if (!status && q->frames_dir) {
            double png_start = q->timing ? wall_seconds() : 0;
            char path[OUTFILE_PATH_MAX];
            snprintf(path, sizeof path, "%s/%05d.png", q->frames_dir, index);
            status = image_write_png_level(frame, path, 2, err, sizeof err);
            if (q->timing) q->timing->png += wall_seconds() - png_start;
        }
        pthread_mutex_lock(&q->lock);
        if (status) {
            q->failed = 1;
            snprintf(q->err, sizeof q->err, "%s", err);
        } else {
            q->consumed++;
        }
        pthread_cond_broadcast(&q->changed);
        pthread_mutex_unlock(&q->lock);
        if (status) return NULL;
    }
}

static void progress(int done, int total, double started, int final)
{
    double elapsed = wall_seconds() - started, rate = done / fmax(elapsed, 1e-9);
    fprintf(stderr, "\rrodsim: frame %d/%d, %.1f frames/s, %.0f s left   ", done, total, rate,
            (total - done) / fmax(rate, 1e-9));
    if (final) fputc('\n', stderr);
}

/* ------------------------------------------------------------------ split frames */

/* Fraction of the height under each view's picture for its name, axes and
 * scale bar (above the overlay's bottom band). */
#define LABEL_ROW 0.08

static const char *const view_labels[] = {"perspective", "orthographic", "top view", "front view",
                                          "side view"};

/* One tile of a split frame: a renderer of its own (camera, grid, shadow
 * map, GL context) drawing a picture as tall as the frame. */
typedef struct view_tile {
    renderer r;
    int made;             /* r was created (destroy it) */
    render_options o;     /* the scene's, with this tile's width, camera and direction */
    image *picture;       /* (o.width x o.height) */
    int x;                /* pixels: the tile's left edge in the frame */
    render_view_kind kind;
} view_tile;

/* Under each tile: its axes, its name and its scale bar; between tiles a
 * thin line. */
static void draw_tile_labels(image *img, const render_overlay *ov, const view_tile *tiles,
                             int count, unsigned show)
{
    int height = img->height, margin = height / 40 + 4;
    int row_top = (int)lround(height * (1 - FRAME_BOTTOM - LABEL_ROW));
    int row_bottom = (int)lround(height * (1 - FRAME_BOTTOM));
    int ascent = text_ascent(ov->body), baseline = (row_top + row_bottom + ascent) / 2;
    double middle = 0.5 * (row_top + row_bottom), triad = 0.28 * (row_bottom - row_top);
    for (int k = 0; k < count; k++) {
        const view_tile *t = &tiles[k];
        if (k > 0) {
            int top = (int)lround(height * FRAME_TOP);
            image_fill_rect(img, t->x - 1, top, 2, row_bottom - top, ov->faint, 0.6);
        }
        int x = t->x + margin;
        if (show & RENDER_SHOW_TRIAD) {
            /* the letters stand up to a letter's width beyond the arrows */
            overlay_draw_triad(img, ov, &t->r.camera, x + triad, middle, triad);
            x += (int)lround(2 * triad + 2 * text_width(ov->body, "x") + 10);
        }
        text_draw(img, ov->body, x, baseline, view_labels[t->kind], ov->ink);
        x += text_width(ov->body, view_labels[t->kind]);
        const render_overlay *own = &t->r.overlay;
        int thick = height / 240 + 2, right = t->x + t->o.width - margin;
        int bar_x = right - own->bar_pixels, bar_y = baseline;
        /* the bar only where it does not run into the name (a narrow tile) */
        if ((show & RENDER_SHOW_SCALE) && own->bar_pixels > 0 &&
            bar_x - 8 - text_width(ov->body, own->bar_label) > x + 12) {
            image_fill_rect(img, bar_x, bar_y - thick, own->bar_pixels, thick, ov->ink, 1.0);
            image_fill_rect(img, bar_x, bar_y - 3 * thick, thick, 3 * thick, ov->ink, 1.0);
            image_fill_rect(img, right - thick, bar_y - 3 * thick, thick, 3 * thick, ov->ink, 1.0);
            text_draw(img, ov->body, bar_x - 8 - text_width(ov->body, own->bar_label), baseline,
                      own->bar_label, ov->ink);
        }
    }
}

/* ------------------------------------------------------------------ the stream */

/* A video being made frame by frame (render.h). */
struct render_stream {
    renderer r;           /* one view (tile_count 0) */
    view_tile *tiles;     /* a split frame: tile_count views, left to right; NULL: one view */
    int tile_count;
    render_overlay overlay; /* a split frame's overlay, drawn once over the tiles */
    render_options overlay_options; /* the scene's, the per-tile items (triad, scale) hidden */
    frame_queue q;
    const render_options *o;
    char poster_path[OUTFILE_PATH_MAX];
    outfile frames_out;   /* the hidden frame directory */
    int all_frames;       /* every frame is drawn (video or PNG frames), else the last only */
    int total;            /* frames to draw */
    int announced, given; /* frames the run will give, frames given so far */
    int threaded;
    pthread_t writer;
    int show_progress;
    double started, last_report, call_start;
    image *last;          /* the last frame drawn: the poster */
    int own_transaction;  /* 1: no caller's transaction; video, poster, frames are ours */
    int status;
    char err[768];
};

/* The tiles of a split frame and its overlay. 0, or -1 with a message
 * (render_stream_destroy frees what was made). */
static int stream_tiles_create(render_stream *st, const rod_recording *extent,
                               const render_options *o, const char *name, char *err,
                               size_t errlen)
{
    int count = o->view_count;
    st->tiles = calloc((size_t)count, sizeof *st->tiles);
    if (!st->tiles) {
        snprintf(err, errlen, "render: out of memory");
        return -1;
    }
    st->tile_count = count;
    /* each picture keeps the overlay's bands free, and a row for its label */
    const frame_band band = {FRAME_TOP, FRAME_BOTTOM + LABEL_ROW, FRAME_SIDE};
    for (int k = 0; k < count; k++) {
        view_tile *t = &st->tiles[k];
        t->x = k * o->width / count;
        t->kind = o->views[k];
        t->o = *o;
        t->o.width = (k + 1) * o->width / count - t->x;
        options_view_camera(t->kind, o->view, &t->o.camera, t->o.view);
        t->o.view_count = 0;
        t->o.overlay = 0; /* drawn once over the whole frame */
        frame_band own = overlay_band(extent, o, band);
        if (k == count - 1 && o->overlay && (o->show & RENDER_SHOW_COLORBAR) &&
            o->color != RENDER_COLOR_SOLID)
            /* the colour bar and its labels (about 0.17 of the height) stand at the
             * right edge: the last view keeps clear of them, on both sides */
            own.side = fmax(band.side, fmin(0.3, 0.17 * o->height / t->o.width));
        if (renderer_create(&t->r, extent, &t->o, name, &own, err, errlen)) return -1;
        t->made = 1;
        t->picture = image_create(t->o.width, t->o.height);
        if (!t->picture) {
            snprintf(err, errlen, "render: out of memory");
            return -1;
        }
    }
    st->overlay_options = *o;
    st->overlay_options.show &= ~(unsigned)(RENDER_SHOW_TRIAD | RENDER_SHOW_SCALE);
    const renderer *first = &st->tiles[0].r;
    return overlay_create(&st->overlay, extent, o, name, first->radius, &first->arrows,
                          &first->camera, o->overlay, err, errlen);
}

/* Draws every tile of a split frame into out, then the overlay once. */
static int stream_draw_tiles(render_stream *st, const rod_recording *rec, int frame, image *out)
{
    for (int k = 0; k < st->tile_count; k++) {
        view_tile *t = &st->tiles[k];
        if (renderer_draw(&t->r, rec, frame, t->picture)) return -1;
        image_mark(out, t->x, 0, t->x + t->o.width, out->height);
        for (int y = 0; y < out->height; y++)
            memcpy(out->rgb + ((size_t)y * (size_t)out->width + (size_t)t->x) * 3,
                   t->picture->rgb + (size_t)y * (size_t)t->o.width * 3, (size_t)t->o.width * 3);
    }
    if (st->o->overlay) {
        overlay_knot(&st->overlay, rec, frame);
        overlay_draw(out, &st->overlay, rec, &st->overlay_options, &st->tiles[0].r.camera, frame);
        draw_tile_labels(out, &st->overlay, st->tiles, st->tile_count, st->o->show);
    }
    return 0;
}

render_stream *render_stream_begin(const rod_recording *extent, const render_options *o,
                                   const char *out_dir, const char *scene_name, int want_video,
                                   int total_frames, char *err, size_t errlen)
{
    if (extent->frame_count < 1 || extent->nodes < 2 || total_frames < 1) {
        snprintf(err, errlen, "render: nothing to render (%d frames, %d nodes)", total_frames,
                 extent->nodes);
        return NULL;
    }
    render_stream *st = calloc(1, sizeof *st);
    if (!st) {
        snprintf(err, errlen, "render: out of memory");
        return NULL;
    }
    st->o = o;
    st->frames_out.fd = st->frames_out.slot = st->frames_out.watch = -1;
    const char *name = scene_name && *scene_name ? scene_name : extent->scene;
    char video_path[OUTFILE_PATH_MAX], frames_dir[OUTFILE_PATH_MAX];
    snprintf(video_path, sizeof video_path, "%s/%s.mp4", out_dir, name);
    snprintf(st->poster_path, sizeof st->poster_path, "%s/%s.png", out_dir, name);
    snprintf(frames_dir, sizeof frames_dir, "%s/%s_frames", out_dir, name);

    if (o->view_count >= 2) {
        if (stream_tiles_create(st, extent, o, name, err, errlen)) {
            render_stream_destroy(st);
            return NULL;
        }
    } else {
        const frame_band band = overlay_band(extent, o, frame_band_full);
        if (renderer_create(&st->r, extent, o, name, &band, err, errlen)) {
            free(st);
            return NULL;
        }
        st->r.draws_overlay = 1;
    }
    /* the video, the poster and the frames appear together, or none */
    st->own_transaction = !outfile_transaction_active();
    if (st->own_transaction) outfile_transaction_begin();
    frame_queue *q = &st->q;
    q->timing = o->timing;
    st->call_start = wall_seconds();
    if (o->timing) memset(o->timing, 0, sizeof *o->timing);
    int status = 0;
    /* each slot tracked: a frame is drawn over the last one in it (renderer.c), and
     * the encoder converts only what changed between frames (video.c) */
    for (int i = 0; i < QUEUE_SLOTS; i++)
        if (!(q->slots[i] = image_create(o->width, o->height)) || image_track_changes(q->slots[i]))
            status = -1;
    if (status) snprintf(err, errlen, "render: out of memory for %dx%d frames", o->width, o->height);
    if (!status && want_video) {
        q->video = video_writer_create(video_path, o->width, o->height, o->fps, o->crf, o->preset,
                                       err, errlen);
        if (!q->video) status = -1;
    }
    /* the frames go to a hidden directory, renamed into place with the other outputs */
    if (!status && o->frames_png) {
        if (outfile_dir_open(&st->frames_out, frames_dir, err, errlen)) status = -1;
        q->frames_dir = st->frames_out.tmp_path;
    }
    st->all_frames = want_video || o->frames_png;
    st->total = st->all_frames ? total_frames : 1;
    if (!status && st->all_frames) {
        st->threaded = 1;
        pthread_mutex_init(&q->lock, NULL);
        pthread_cond_init(&q->changed, NULL);
        if (pthread_create(&st->writer, NULL, writer_thread, q)) {
            snprintf(err, errlen, "render: cannot start the writer thread");
            pthread_mutex_destroy(&q->lock);
            pthread_cond_destroy(&q->changed);
            st->threaded = 0;
            status = -1;
        }
    }
    if (status) {
        render_stream_destroy(st);
        return NULL;
    }
    st->show_progress = isatty(2) && st->total > 1;
    st->started = wall_seconds();
    st->last = q->slots[0];
    st->announced = total_frames;
    return st;
}

/* The cameras of frame k, for the tests (render_options.cameras). */
static void report_cameras(const render_stream *st, int k)
{
    const render_options *o = st->o;
    int views = st->tile_count > 0 ? st->tile_count : 1;
    for (int v = 0; o->cameras && v < views; v++) {
        long index = (long)k * views + v;
        if (index < o->camera_capacity)
            o->cameras[index] = st->tile_count ? st->tiles[v].r.camera : st->r.camera;
    }
}

int render_stream_frame(render_stream *st, const rod_recording *rec, int frame, char *err,
                        size_t errlen)
{
    int index = st->given++;
    frame_queue *q = &st->q;
    if (st->status) {
        snprintf(err, errlen, "%s", st->err);
        return -1;
    }
    /* poster only: draw just the last frame (the one before it gives the speed) */
    if (!st->all_frames && index + 1 < st->announced) {
        if (st->tile_count == 0) renderer_remember(&st->r, rec, frame);
        for (int t = 0; t < st->tile_count; t++) renderer_remember(&st->tiles[t].r, rec, frame);
        return 0;
    }
    int k = st->all_frames ? index : 0;
    if (st->threaded) {
        double wait_start = st->o->timing ? wall_seconds() : 0;
        pthread_mutex_lock(&q->lock);
        while (q->produced - q->consumed == QUEUE_SLOTS && !q->failed)
            pthread_cond_wait(&q->changed, &q->lock);
        int failed = q->failed;
        if (failed) snprintf(st->err, sizeof st->err, "%s", q->err);
        pthread_mutex_unlock(&q->lock);
        if (st->o->timing) st->o->timing->wait += wall_seconds() - wait_start;
        if (failed) {
            st->status = -1;
            snprintf(err, errlen, "%s", st->err);
            return -1;
        }
    }
    st->last = q->slots[k % QUEUE_SLOTS];
    if (st->tile_count ? stream_draw_tiles(st, rec, frame, st->last)
                       : renderer_draw(&st->r, rec, frame, st->last)) {
        snprintf(st->err, sizeof st->err, "render: OpenGL failed while drawing frame %d", index);
        st->status = -1;
        snprintf(err, errlen, "%s", st->err);
        return -1;
    }
    report_cameras(st, k);
    if (st->threaded) {
        pthread_mutex_lock(&q->lock);
        q->produced++;
        pthread_cond_broadcast(&q->changed);
        pthread_mutex_unlock(&q->lock);
    }
    if (st->show_progress && (wall_seconds() - st->last_report > 0.25 || k + 1 == st->total)) {
        st->last_report = wall_seconds();
        progress(k + 1, st->total, st->started, k + 1 == st->total);
    }
    return 0;
}

/* Stops the writer thread after the frames it holds; 0, or -1 (message in st->err). */
static int stop_writer(render_stream *st)
{
    if (!st->threaded) return 0;
    frame_queue *q = &st->q;
    pthread_mutex_lock(&q->lock);
    q->done = 1;
    pthread_cond_broadcast(&q->changed);
    pthread_mutex_unlock(&q->lock);
    pthread_join(st->writer, NULL);
    pthread_mutex_destroy(&q->lock);
    pthread_cond_destroy(&q->changed);
    st->threaded = 0;
    if (q->failed) {
        snprintf(st->err, sizeof st->err, "%s", q->err);
        return -1;
    }
    return 0;
}

int render_stream_finish(render_stream *st, char *err, size_t errlen)
{
    const render_options *o = st->o;
    frame_queue *q = &st->q;
    int status = st->status;
    if (!status && st->given != st->announced) {
        snprintf(st->err, sizeof st->err, "render: %d frames given, %d announced", st->given,
                 st->announced);
        status = -1;
    }
    if (stop_writer(st) && !status) status = -1;
    if (!status && q->video && video_writer_finish(q->video, st->err, sizeof st->err))
        status = -1;
    if (o->timing) {
        if (q->video) video_writer_times(q->video, &o->timing->convert, &o->timing->encode);
        o->timing->frames = q->consumed;
        o->timing->wall = wall_seconds() - st->call_start;
    }
    if (!status && o->poster && image_write_png(st->last, st->poster_path, st->err, sizeof st->err))
        status = -1;
    if (!status && q->frames_dir && outfile_commit(&st->frames_out, st->err, sizeof st->err))
        status = -1;
    if (!status && st->own_transaction) {
        status = outfile_transaction_commit(st->err, sizeof st->err) ? -1 : 0;
        st->own_transaction = 0;
    }
    st->status = status;
    if (status) snprintf(err, errlen, "%s", st->err);
    return status;
}

void render_stream_destroy(render_stream *st)
{
    if (!st) return;
    stop_writer(st);
    outfile_abort(&st->frames_out); /* unless committed: no partial frame sequence */
    video_writer_destroy(st->q.video); /* removes the video unless finished */
    for (int i = 0; i < QUEUE_SLOTS; i++) image_destroy(st->q.slots[i]);
    if (st->own_transaction) outfile_transaction_abort();
    if (st->tiles) {
        for (int k = 0; k < st->tile_count; k++) {
            if (st->tiles[k].made) renderer_destroy(&st->tiles[k].r);
            image_destroy(st->tiles[k].picture);
        }
        free(st->tiles);
        overlay_destroy(&st->overlay);
    } else {
        renderer_destroy(&st->r);
    }
    free(st);
}

int render_recording(const rod_recording *rec, const render_options *o, const char *out_dir,
                     const char *scene_name, int want_video, char *err, size_t errlen)
{
    render_stream *st = render_stream_begin(rec, o, out_dir, scene_name, want_video,
                                            rec->frame_count, err, errlen);
    if (!st) return -1;
    int status = 0;
    for (int k = 0; !status && k < rec->frame_count; k++)
        status = render_stream_frame(st, rec, k, err, errlen);
    if (!status) status = render_stream_finish(st, err, errlen);
    render_stream_destroy(st);
    return status;
}
