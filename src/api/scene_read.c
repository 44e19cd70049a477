/* scene_read.c: a rod scene read whole (see scene_read.h). */
#include "api/scene_read.h"

#include <stdio.h>

#include "api/scene_keys.h"
#include "render/render.h"
#include "sim/scene.h"

int run_read_output(ini_doc *doc, run_output *out, char *err, size_t errlen)
{
    /* one set of defaults and range checks for [render]: the renderer's,
     * so that no default (crf) can differ between the two */
    render_options_default(&out->render);
    if (render_options_read(doc, &out->render, err, errlen)) return -1;
    out->fps = render_output_rate(&out->render); /* fps / speed frames per simulated s */
    out->width = out->render.width;
    out->height = out->render.height;
    out->crf = out->render.crf;
    return 0;
}

int run_read_scene(ini_doc *doc, rod_model *m, run_output *out, char *err, size_t errlen)
{
    /* unknown keys first, at their own line: a misspelt required
     * key would otherwise be reported as a missing one */
    if (scene_refuse_beam(doc, err, errlen) || ini_check_keys(doc, scene_keys_rod, err, errlen)) {
        *m = rod_model_default();
        return -1;
    }
    const char *name[1];
    if (ini_section_names(doc, "rod", name, 1) > 0) {
        *m = rod_model_default();
        char section[96];
        snprintf(section, sizeof section, "rod %.80s", name[0]);
        snprintf(err, errlen, "%s:%d: [%s]: a scene of named rods is run by `rodsim run` "
                 "only; accepted here: one bare [rod]", ini_filename(doc),
                 ini_section_line(doc, section, 0), section);
        return -1;
    }
    if (scene_read_rod(doc, m, err, errlen)) return -1;
    if (run_read_output(doc, out, err, errlen) || ini_check_unused(doc, err, errlen)) {
        rod_model_release(m);
        return -1;
    }
    return 0;
}

int run_write_video(const rod_recording *rec, const run_output *out, const char *out_dir,
                    char *err, size_t errlen)
{
    return render_recording(rec, &out->render, out_dir, rec->scene, 1, err, errlen);
}
