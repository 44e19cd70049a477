/* summary.c: the run summary as JSON (see summary.h). */
#include "cli/summary.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/outfile.h"

void summary_init(run_summary *s)
{
    memset(s, 0, sizeof *s);
    s->rope_in_knot_d = NAN;
    s->min_strand_gap_d = INFINITY;
    s->min_instrument_gap = INFINITY;
}

static void copy_text(char *dst, size_t n, const char *src)
{
    snprintf(dst, n, "%s", src ? src : "");
}

void summary_add_warning(run_summary *s, const char *text)
{
    if (s->warning_count < SUMMARY_MAX_WARNINGS)
        copy_text(s->warnings[s->warning_count++], SUMMARY_TEXT_LEN, text);
}

void summary_add_file(run_summary *s, const char *path)
{
    if (s->file_count < SUMMARY_MAX_FILES)
        copy_text(s->files[s->file_count++], SUMMARY_TEXT_LEN, path);
}

void summary_set_message(run_summary *s, const char *text)
{
    if (!s->message[0]) copy_text(s->message, sizeof s->message, text);
}

const char *summary_status(const run_summary *s)
{
    if (s->status) return s->status;
    return s->exit_code == 0 ? "ok" : s->exit_code == 2 ? "refused" : "failed";
}

void summary_json_string(FILE *f, const char *text)
{
    fputc('"', f);
    for (const unsigned char *c = (const unsigned char *)text; *c; c++) {
        switch (*c) {
        case '"': fputs("\\\"", f); break;
        case '\\': fputs("\\\\", f); break;
        case '\n': fputs("\\n", f); break;
        case '\r': fputs("\\r", f); break;
        case '\t': fputs("\\t", f); break;
        default:
            if (*c < 0x20) fprintf(f, "\\u%04x", *c);
            else fputc(*c, f);
        }
    }
    fputc('"', f);
}

void summary_json_number(FILE *f, double x)
{
    if (!isfinite(x)) {
        fputs("null", f);
        return;
    }
    /* the shortest of %.15g .. %.17g that reads back as the same double */
    char text[32];
    for (int digits = 15; digits <= 17; digits++) {
        snprintf(text, sizeof text, "%.*g", digits, x + 0.0); /* + 0.0: -0 as 0 */
        if (strtod(text, NULL) == x) break;
    }
    fputs(text, f);
}

/* ---- a tiny writer: keys and commas ------------------------------------- */

typedef struct json_out {
    FILE *f;
    int first; /* 1: no member yet in the innermost object or array */
} json_out;

static void comma(json_out *j)
{
    if (!j->first) fputc(',', j->f);
    j->first = 0;
}

static void key(json_out *j, const char *name)
{
    comma(j);
    summary_json_string(j->f, name);
    fputc(':', j->f);
}

static void open_(json_out *j, char bracket)
{
    fputc(bracket, j->f);
    j->first = 1;
}

static void close_(json_out *j, char bracket)
{
    fputc(bracket, j->f);
    j->first = 0;
}

static void number_field(json_out *j, const char *name, double x)
{
    key(j, name);
    summary_json_number(j->f, x);
}

static void string_field(json_out *j, const char *name, const char *text)
{
    key(j, name);
    summary_json_string(j->f, text);
}

static void vector_field(json_out *j, const char *name, const double *v)
{
    key(j, name);
    open_(j, '[');
    for (int k = 0; k < 3; k++) {
        comma(j);
        summary_json_number(j->f, v[k]);
    }
    close_(j, ']');
}

static void string_list(json_out *j, const char *name, int count,
                        const char (*items)[SUMMARY_TEXT_LEN])
{
    key(j, name);
    open_(j, '[');
    for (int i = 0; i < count; i++) {
        comma(j);
        summary_json_string(j->f, items[i]);
    }
    close_(j, ']');
}

static void knot_object(json_out *j, const summary_rod_knot *k)
{
    key(j, "knot");
    open_(j, '{');
    string_field(j, "type", k->type);
    key(j, "alexander");
    open_(j, '[');
    for (int i = 0; i < k->terms; i++) {
        comma(j);
        fprintf(j->f, "%lld", k->alexander[i]);
    }
    close_(j, ']');
    key(j, "determinant");
    fprintf(j->f, "%lld", k->determinant);
    if (k->has_signature) number_field(j, "signature", k->signature);
    if (isfinite(k->rope_d)) number_field(j, "rope_in_knot_d", k->rope_d);
    key(j, "changes");
    open_(j, '[');
    for (int i = 0; i < k->change_count; i++) {
        comma(j);
        open_(j, '[');
        comma(j);
        summary_json_number(j->f, k->changes[i].t);
        comma(j);
        summary_json_string(j->f, k->changes[i].type);
        close_(j, ']');
    }
    close_(j, ']');
    /* How each change came, beside `changes` and in its order, so that
     * `changes` keeps its fixed [t, type] pairs: "" where no end was
     * involved. Left out when no change says how. */
    int any_how = 0;
    for (int i = 0; i < k->change_count; i++) any_how |= k->changes[i].how[0] != '\0';
    if (any_how) {
        key(j, "changes_how");
        open_(j, '[');
        for (int i = 0; i < k->change_count; i++) {
            comma(j);
            summary_json_string(j->f, k->changes[i].how);
        }
        close_(j, ']');
    }
    close_(j, '}');
}

/* The single rod's knot fields as a rod's knot */
static void single_knot(const run_summary *s, summary_rod_knot *k)
{
    snprintf(k->type, sizeof k->type, "%s", s->knot_type);
    k->terms = s->knot_terms < 32 ? s->knot_terms : 32;
    memcpy(k->alexander, s->knot_alexander, sizeof k->alexander);
    k->determinant = s->knot_determinant;
    k->has_signature = s->knot_has_signature;
    k->signature = s->knot_signature;
    k->rope_d = s->rope_in_knot_d;
    k->change_count = s->knot_change_count < SUMMARY_MAX_KNOT_CHANGES
                          ? s->knot_change_count : SUMMARY_MAX_KNOT_CHANGES;
    memcpy(k->changes, s->knot_changes, sizeof k->changes);
}

static void rod_object(json_out *j, const run_summary *s)
{
    static const char *const end_names[2] = {"root", "tip"};
    open_(j, '{');
    string_field(j, "name", "rod");
    number_field(j, "nodes", s->nodes);
    vector_field(j, "tip", s->tip);
    key(j, "ends");
    open_(j, '{');
    for (int e = 0; e < 2; e++) {
        if (!s->has_end[e]) continue;
        key(j, end_names[e]);
        open_(j, '{');
        vector_field(j, "force", s->end_force[e]);
        vector_field(j, "moment", s->end_moment[e]);
        close_(j, '}');
    }
    close_(j, '}');
    if (s->has_knot) {
        summary_rod_knot k;
        single_knot(s, &k);
        knot_object(j, &k);
    }
    if (isfinite(s->min_strand_gap_d)) number_field(j, "min_strand_gap_d", s->min_strand_gap_d);
    close_(j, '}');
}

/* One rod of a scene of several: the single rod's fields, and its
 * contact force */
static void set_rod_object(json_out *j, const summary_rod *r)
{
    static const char *const end_names[2] = {"root", "tip"};
    open_(j, '{');
    string_field(j, "name", r->name);
    number_field(j, "nodes", r->nodes);
    vector_field(j, "tip", r->tip);
    key(j, "ends");
    open_(j, '{');
    for (int e = 0; e < 2; e++) {
        if (!r->has_end[e]) continue;
        key(j, end_names[e]);
        open_(j, '{');
        vector_field(j, "force", r->end_force[e]);
        vector_field(j, "moment", r->end_moment[e]);
        close_(j, '}');
    }
    close_(j, '}');
    vector_field(j, "contact_force", r->contact_force);
    if (r->has_knot) knot_object(j, &r->knot);
    if (isfinite(r->min_strand_gap_d)) number_field(j, "min_strand_gap_d", r->min_strand_gap_d);
    close_(j, '}');
}

/* The knots two rods make together: rods [a, b] and the knot */
static void knots_across_list(json_out *j, const run_summary *s)
{
    key(j, "knots_across");
    open_(j, '[');
    for (int i = 0; i < s->knot_across_count && i < SUMMARY_MAX_KNOTS_ACROSS; i++) {
        const summary_knot_across *k = &s->knots_across[i];
        comma(j);
        open_(j, '{');
        key(j, "rods");
        open_(j, '[');
        for (int r = 0; r < 2; r++) {
            comma(j);
            summary_json_string(j->f, k->rods[r]);
        }
        close_(j, ']');
        knot_object(j, &k->knot);
        close_(j, '}');
    }
    close_(j, ']');
}

static void punctures_list(json_out *j, const run_summary *s)
{
    key(j, "punctures");
    open_(j, '[');
    for (int i = 0; i < s->puncture_count; i++) {
        comma(j);
        open_(j, '{');
        if (s->punctures[i].rod[0]) string_field(j, "rod", s->punctures[i].rod);
        number_field(j, "t", s->punctures[i].t);
        vector_field(j, "point", s->punctures[i].point);
        vector_field(j, "force", s->punctures[i].force);
        close_(j, '}');
    }
    close_(j, ']');
}

static void grasps_list(json_out *j, const run_summary *s)
{
    key(j, "grasps");
    open_(j, '[');
    for (int i = 0; i < s->grasp_count; i++) {
        const summary_grasp *g = &s->grasps[i];
        comma(j);
        open_(j, '{');
        string_field(j, "instrument", g->instrument);
        if (g->rod[0]) string_field(j, "rod", g->rod);
        number_field(j, "t_on", g->t_on);
        if (g->t_off >= 0.0) number_field(j, "t_off", g->t_off); /* absent: held at the end */
        number_field(j, "s", g->s);
        number_field(j, "force", g->force);
        close_(j, '}');
    }
    close_(j, ']');
}

/* The closest two instruments came: the gap (m), and where */
static void instrument_gap(json_out *j, const run_summary *s)
{
    number_field(j, "min_instrument_gap", s->min_instrument_gap);
    key(j, "min_instrument_gap_at");
    open_(j, '{');
    number_field(j, "t", s->min_instrument_gap_t);
    key(j, "instruments");
    open_(j, '[');
    for (int i = 0; i < 2; i++) {
        comma(j);
        summary_json_string(j->f, s->min_instrument_gap_between[i]);
    }
    close_(j, ']');
    key(j, "parts");
    open_(j, '[');
    for (int i = 0; i < 2; i++) {
        comma(j);
        summary_json_string(j->f, s->min_instrument_gap_parts[i]);
    }
    close_(j, ']');
    close_(j, '}');
}

static void needle_grasps_list(json_out *j, const run_summary *s)
{
    key(j, "needle_grasps");
    open_(j, '[');
    for (int i = 0; i < s->needle_grasp_count; i++) {
        const summary_needle_grasp *g = &s->needle_grasps[i];
        comma(j);
        open_(j, '{');
        number_field(j, "t", g->t);
        string_field(j, "from", g->from);
        string_field(j, "to", g->to);
        close_(j, '}');
    }
    close_(j, ']');
}

static void cuts_list(json_out *j, const run_summary *s)
{
    key(j, "cuts");
    open_(j, '[');
    for (int i = 0; i < s->cut_count; i++) {
        const summary_cut *c = &s->cuts[i];
        comma(j);
        open_(j, '{');
        if (c->instrument[0]) string_field(j, "instrument", c->instrument); /* absent: [cut] */
        if (c->rod[0]) string_field(j, "rod", c->rod);
        number_field(j, "t", c->t);
        number_field(j, "s", c->s);
        number_field(j, "removed", c->removed);
        close_(j, '}');
    }
    close_(j, ']');
}

static void tissue_object(json_out *j, const run_summary *s)
{
    key(j, "tissue");
    open_(j, '{');
    string_field(j, "model", "elastic");
    number_field(j, "max_displacement", s->tissue_max_displacement);
    key(j, "wound_gap");
    open_(j, '[');
    for (int i = 0; i < s->gap_count; i++) {
        comma(j);
        fputc('[', j->f);
        summary_json_number(j->f, s->wound_gap[i][0]);
        fputc(',', j->f);
        summary_json_number(j->f, s->wound_gap[i][1]);
        fputc(']', j->f);
    }
    close_(j, ']');
    if (s->stitch_count > 0) { /* several rods: the gap at each stitch */
        key(j, "stitches");
        open_(j, '[');
        for (int k = 0; k < s->stitch_count; k++) {
            comma(j);
            open_(j, '{');
            string_field(j, "rod", s->stitch_rod[k]);
            key(j, "gap");
            open_(j, '[');
            for (int i = 0; i < s->gap_count; i++) {
                comma(j);
                fputc('[', j->f);
                summary_json_number(j->f, s->wound_gap[i][0]);
                fputc(',', j->f);
                summary_json_number(j->f, s->stitch_gap[i][k]);
                fputc(']', j->f);
            }
            close_(j, ']');
            close_(j, '}');
        }
        close_(j, ']');
    }
    close_(j, '}');
}

int summary_print(FILE *f, const run_summary *s)
{
    json_out j = {.f = f, .first = 1};
    open_(&j, '{');
    string_field(&j, "status", summary_status(s));
    number_field(&j, "exit_code", s->exit_code);
    if (s->message[0]) string_field(&j, "message", s->message);
    string_list(&j, "warnings", s->warning_count, s->warnings);
    if (s->scene[0]) string_field(&j, "scene", s->scene);
    if (s->scheme[0]) string_field(&j, "scheme", s->scheme);
    if (s->has_run) {
        number_field(&j, "steps", (double)s->steps);
        number_field(&j, "frames", (double)s->frames);
    }
    if (s->has_video_rate) {
        number_field(&j, "fps", s->fps);
        number_field(&j, "speed", s->speed);
    }
    if (s->has_run) number_field(&j, "t_end", s->t_end);
    number_field(&j, "cpu_s", s->cpu_s);
    number_field(&j, "wall_s", s->wall_s);
    if (s->has_run && s->t_end > 0.0) number_field(&j, "cpu_s_per_sim_s", s->cpu_s / s->t_end);
    if (s->has_run && s->steps > 0 && s->step_cpu_s > 0.0)
        number_field(&j, "cpu_us_per_step", 1e6 * s->step_cpu_s / (double)s->steps);
    if (s->gl[0]) string_field(&j, "gl", s->gl);
    string_list(&j, "files", s->file_count, s->files);
    if (s->rod_count > 0) {
        key(&j, "rods");
        open_(&j, '[');
        for (int k = 0; k < s->rod_count && k < SUMMARY_MAX_RODS; k++) {
            comma(&j);
            set_rod_object(&j, &s->rods[k]);
        }
        close_(&j, ']');
        if (s->knot_across_count > 0) knots_across_list(&j, s);
    } else if (s->has_rod) {
        key(&j, "rods");
        open_(&j, '[');
        comma(&j);
        rod_object(&j, s);
        close_(&j, ']');
    }
    if (s->puncture_count > 0) punctures_list(&j, s);
    if (s->grasp_count > 0) grasps_list(&j, s);
    if (s->cut_count > 0) cuts_list(&j, s);
    if (s->needle_grasp_count > 0) needle_grasps_list(&j, s);
    if (isfinite(s->min_instrument_gap)) instrument_gap(&j, s);
    if (s->has_tissue) tissue_object(&j, s);
    close_(&j, '}');
    fputc('\n', f);
    return ferror(f) ? -1 : 0;
}

int summary_write(const char *path, const run_summary *s, char *err, size_t errlen)
{
    if (strcmp(path, "-") == 0) {
        if (summary_print(stdout, s) || fflush(stdout) != 0) {
            snprintf(err, errlen, "--summary: cannot write to standard output");
            return -1;
        }
        return 0;
    }
    outfile file = {.fd = -1, .slot = -1};
    if (outfile_open(&file, path, err, errlen)) return -1;
    if (summary_print(file.fp, s) || fflush(file.fp) != 0) {
        snprintf(err, errlen, "--summary %s: write failed (disk full?)", path);
        outfile_abort(&file);
        return -1;
    }
    return outfile_commit(&file, err, errlen);
}
