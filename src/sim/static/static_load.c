/* static_load.c: what a static step's continuation follows (static_load,
 * static_internal.h): the loads and the held ends' poses at a time, and
 * the load in words for the room's messages. It reads the ends' initial
 * poses static_work.c keeps and calls no other file of the room. */
#include "sim/static/static_load.h"

#include <stdio.h>
#include <string.h>

#include "sim/path.h"
#include "sim/rod.h"
#include "sim/static/static_internal.h"
#include "base/vec3.h"

/* The loads and the held ends' poses at time t: a driven end on its path
 * (position, and rotation from its initial frame), a held one where it
 * started (decided: a path's rotation is used only by a clamped end held in
 * place; a pinned end turns freely and a sliding clamp keeps d3 along its
 * slide). */
void static_target_load(const static_work *w, const rod_model *m, double t, static_load *load)
{
    memset(load, 0, sizeof *load);
    rod_tip_load(m, t, load->tip_force, load->tip_moment);
    v3_copy(load->distributed, m->distributed_force);
    v3_copy(load->distributed_moment, m->distributed_moment);
    load->point_factor = rod_profile_factor(&m->profile, t);
    load->curvature = 1.0;
    v3_copy(load->root_position, w->root_position0);
    v3_copy(load->tip_position, w->tip_position0);
    m3_identity(load->root_rotation);
    m3_identity(load->tip_rotation);
    const rod_path *paths[2] = {m->root_motion, m->tip_motion};
    double *positions[2] = {load->root_position, load->tip_position};
    double *rotations[2] = {load->root_rotation, load->tip_rotation};
    for (int e = 0; e < 2; e++) {
        if (!paths[e]) continue;
        rod_pose pose;
        rod_path_eval(paths[e], t, &pose);
        v3_copy(positions[e], pose.position);
        memcpy(rotations[e], pose.rotation, sizeof pose.rotation);
    }
}

/* The load in words, for messages. */
void static_describe_load(const rod_model *m, const static_load *load, char *text, size_t length)
{
    snprintf(text, length,
             "tip force %g %g %g N, tip moment %g %g %g N m on the %s frame, distributed %g %g %g N/m",
             load->tip_force[0], load->tip_force[1], load->tip_force[2], load->tip_moment[0],
             load->tip_moment[1], load->tip_moment[2],
             m->tip_frame == ROD_FRAME_DIRECTOR ? "tip director" : "global",
             load->distributed[0], load->distributed[1], load->distributed[2]);
}
