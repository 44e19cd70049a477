/* render_types.h: the plain types every part of the renderer shares, at the
 * bottom of the render floor: the camera, a vertex of the drawn geometry,
 * the key light that rides with the camera and the palette. The geometry
 * (mesh.c, camera.c) makes them, the GL layer (gl_render.c) draws them; this
 * header includes no other part of the renderer, so no include runs back up. */
#ifndef RODSIM_RENDER_TYPES_H
#define RODSIM_RENDER_TYPES_H

/* A camera: matrices are column-major 4x4 (OpenGL's layout). */
typedef struct render_camera {
    int width, height;          /* pixels */
    int orthographic;
    double eye[3], target[3];   /* m */
    double direction[3];        /* unit, from the target to the eye */
    double right[3], up[3];     /* unit, screen axes in the world */
    double view[16], projection[16], view_projection[16];
    double metres_per_pixel;    /* at the target's depth */
    double fovy;                /* rad, perspective's vertical field of view; 0: the
                                   default PERSPECTIVE_FOVY (camera.h) */
} render_camera;

/* The key light's direction (unit, towards the light): it rides with the
 * camera, from upper left in front, so the picture reads the same from any
 * view; the shading and the shadows use it. */
void render_key_light(const render_camera *cam, double key[3]);

/* One vertex of the drawn geometry: world position (m), unit normal, colour. */
typedef struct render_vertex {
    float position[3], normal[3], color[3];
} render_vertex;

/* Colours the tests can look for (linear 0..1 before lighting). */
extern const float render_rod_color[3];
extern const float render_stripe_color[3];
extern const float render_clamp_color[3];  /* block of a clamped end */
extern const float render_ball_color[3];   /* ball of a pinned end */
extern const float render_needle_color[3]; /* the needle */
extern const float render_skin_color[3];   /* a tissue surface (matte) */
extern const float render_surface_color[3]; /* any other surface and the ground (matte) */
extern const float render_wound_color[3];  /* the wound line */
extern const float render_puncture_color[3]; /* a puncture's ring */
extern const float render_dermis_color[3];   /* a cut tissue's face, under the skin's top */
extern const float render_subcutis_color[3]; /* a cut tissue's face, below the dermis (fat) */
/* the stripe over a colour map: white, since the amber one would read as a
 * value (viridis ends in yellow) */
extern const float render_stripe_on_map_color[3];
extern const float render_force_color[3];  /* the tip force's arrow */
extern const float render_moment_color[3]; /* the tip moment's arrow */

#endif
