/* render_types.c: the key light and the palette (render_types.h). */
#include "render/render_types.h"

#include "base/vec3.h"

/* steel blue; bytes 2e66c7 so that [render] rod_color = 2e66c7 is exactly the default */
const float render_rod_color[3] = {0x2e / 255.0f, 0x66 / 255.0f, 0xc7 / 255.0f};
const float render_stripe_color[3] = {1.00f, 0.76f, 0.08f}; /* amber */
const float render_clamp_color[3] = {0.42f, 0.43f, 0.46f};  /* dark steel */
const float render_ball_color[3] = {0.70f, 0.42f, 0.16f};   /* bronze, apart from the rest */
const float render_needle_color[3] = {0.74f, 0.75f, 0.77f}; /* bright steel, lighter than the rod */
const float render_skin_color[3] = {0.80f, 0.56f, 0.45f};    /* a light skin tone, matte */
const float render_surface_color[3] = {0.90f, 0.90f, 0.88f}; /* neutral light grey */
const float render_wound_color[3] = {0.42f, 0.05f, 0.06f};   /* dark red */
const float render_puncture_color[3] = {0.20f, 0.04f, 0.05f}; /* nearly black red */
const float render_dermis_color[3] = {0.78f, 0.30f, 0.32f};   /* a raw flesh red */
const float render_subcutis_color[3] = {0.98f, 0.82f, 0.42f}; /* the fat's pale yellow */
const float render_stripe_on_map_color[3] = {0.97f, 0.97f, 0.97f};
const float render_force_color[3] = {0.86f, 0.16f, 0.14f};
const float render_moment_color[3] = {0.16f, 0.62f, 0.26f};

void render_key_light(const render_camera *cam, double key[3])
{
    const double *d = cam->direction, *u = cam->up, *rt = cam->right;
    for (int c = 0; c < 3; c++) key[c] = d[c] + 0.6 * u[c] - 0.5 * rt[c];
    v3_scale(key, key, 1.0 / v3_norm(key));
}
