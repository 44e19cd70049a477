/* instrument_mesh.h: the surgical instruments of a recording, drawn, pure
 * C: each kind recognisable at its real size (sim/recording.h
 * recording_instrument): a needle holder's short jaws, box lock, crossed
 * shanks and ring handles; forceps' two tines sprung from their back end;
 * scissors' long blades, screw, shanks and rings; in bright steel. The jaws
 * and shanks are the tubes the thread touches (their contact capsules). */
#ifndef RODSIM_RENDER_INSTRUMENT_MESH_H
#define RODSIM_RENDER_INSTRUMENT_MESH_H

#include "render/mesh.h"
#include "sim/recording.h"

/* Room one instrument takes in a mesh */
#define INSTRUMENT_MESH_VERTICES 2400
#define INSTRUMENT_MESH_INDICES 13000
/* The points instrument_mesh_points gives for one instrument */
#define INSTRUMENT_MESH_POINTS 16

/* Every instrument of rec in `frame` into m, closed jaws `gap` apart (m:
 * the drawn thread's diameter, so that a grasped thread shows between them
 * rather than through them). */
void instrument_mesh_add(render_mesh *m, const rod_recording *rec, int frame, double gap);

/* Points of instrument k's parts in `frame` (global, m) into out (3 x
 * INSTRUMENT_MESH_POINTS), 8 per side: its jaw's two ends, its shank's two
 * ends (pairs: the tubes' axes), the 4 corners of its ring handle's box (a
 * hull); each padded by *pad (m). Returns INSTRUMENT_MESH_POINTS, or 0 (none). */
int instrument_mesh_points(const rod_recording *rec, int frame, int k, double gap, double *out,
                           double *pad);

#endif
