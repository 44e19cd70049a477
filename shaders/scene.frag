#version 330 core
// Blinn-Phong with a key and a fill light (directional), plus ambient; the
// key light's shadow from a shadow map, its edge softened by one bilinear
// depth comparison (percentage-closer filtering, PCF, of 2 x 2 texels).
in vec3 world_position;
in vec3 world_normal;
in vec3 base_color;

// LIT and FADING are defined by the program that compiles this (src/render/gl_render.c):
// one variant each, so that no pixel pays for another kind's shading
const int lit = LIT;          // 0: flat colour (grid lines); 1: glossy (rod); 2: matte (surfaces)
uniform int orthographic;     // 1: the eye direction is the same everywhere
uniform vec3 eye;             // world position of the camera (perspective)
uniform vec3 view_direction;  // unit, from the scene towards the eye (orthographic)
uniform vec3 key_direction;   // unit, towards the key light
uniform vec3 fill_direction;  // unit, towards the fill light
uniform int shadows;          // 1: the key light is blocked where the shadow map says so
uniform sampler2DShadow shadow_map;
uniform mat4 light_view_projection;
uniform float shadow_offset;  // m: the point looked up moves this far along its normal (no acne)
uniform vec4 unshadowed;      // xyz: faces of this unit normal receive no shadow (a cutaway's
                              // cap, where no light falls); w 1: on, 0: off
const int fading = FADING;    // 1: fade to the background away from fade_centre (a plane)
uniform vec4 fade;            // xyz: centre (m); w: radius where the fade starts (m)
uniform float fade_end;       // m: radius where only the background remains
uniform vec3 background;      // linear 0..1

layout(location = 0) out vec4 frag_color;
// CACHE 1 (the static receivers drawn once for a still camera, matte only):
// the colour lit, the look-up of the shadow map and what the key light's
// shadow may take from the colour, so that a frame darkens the backdrop
// (gl_renderer_darken in src/render/gl_render.c, the same comparison as
// key_visibility) instead of drawing the receivers again
#if CACHE
layout(location = 1) out vec4 cache_look_up;  // xyz: the shadow map's coordinates; w 1: looked up
layout(location = 2) out vec4 cache_key;      // rgb: the colour lit less the colour in full shadow
#endif

// The shadow map's coordinates of p (orthographic: w = 1), moved along n
vec3 look_up(vec3 p, vec3 n)
{
    vec4 q = light_view_projection * vec4(p + shadow_offset * n, 1.0);
    return q.xyz * 0.5 + 0.5;
}

// The fraction of the key light that reaches p (1: lit, 0: in shadow):
// one bilinear comparison, a tent filter two texels wide; the map's texels
// are sized for it (src/render/shadow.c). Each tap costs as much as the rest
// of the shading on llvmpipe (docs/decisions/0105-video-speed.md).
float key_visibility(vec3 p, vec3 n)
{
    vec3 c = look_up(p, n);
    if (c.x < 0.0 || c.x > 1.0 || c.y < 0.0 || c.y > 1.0) return 1.0;
    // beyond the far plane is behind every caster; nearer than the near plane, before them
    float ref = clamp(c.z, 0.0, 1.0);
    return texture(shadow_map, vec3(c.xy, ref));
}

// The colour of the surface of unit normal n with the given part of the key light
vec3 shaded(vec3 n, float visible)
{
    vec3 v = orthographic == 1 ? view_direction : normalize(eye - world_position);
    if (dot(n, v) < 0.0) n = -n;  // two-sided: caps and ribbons seen from behind
    float key_diffuse = max(dot(n, key_direction), 0.0) * visible;
    float fill_diffuse = max(dot(n, fill_direction), 0.0);
    vec3 c;
    if (lit == 2) {
        // matte (skin, table): no highlight, more ambient so that a shadow reads as one
        c = base_color * (0.40 + 0.60 * key_diffuse + 0.15 * fill_diffuse);
    } else {
        vec3 h = normalize(key_direction + v);
        float specular = pow(max(dot(n, h), 0.0), 48.0) * (key_diffuse > 0.0 ? visible : 0.0);
        c = base_color * (0.22 + 0.78 * key_diffuse + 0.30 * fill_diffuse) + vec3(0.35 * specular);
    }
    c = min(c, vec3(1.0));
    if (fading == 1) {
        float d = distance(world_position, fade.xyz);
        c = mix(c, background, smoothstep(fade.w, fade_end, d));
    }
    return c;
}

void main()
{
    if (lit == 0) {
        frag_color = vec4(base_color, 1.0);
#if CACHE
        cache_look_up = vec4(0.0);
        cache_key = vec4(0.0);
#endif
        return;
    }
    vec3 n = normalize(world_normal);
    // a side turned from the key light has no key light to lose; a section's face none to
    bool keyed = shadows == 1 && dot(n, key_direction) > 0.0 &&
                 !(unshadowed.w > 0.5 && dot(n, unshadowed.xyz) > 0.9999);
#if CACHE
    vec3 c = shaded(n, 1.0);
    frag_color = vec4(c, 1.0);
    cache_look_up = keyed ? vec4(look_up(world_position, n), 1.0) : vec4(0.0);
    cache_key = vec4(keyed ? c - shaded(n, 0.0) : vec3(0.0), 0.0);
#else
    float visible = keyed ? key_visibility(world_position, n) : 1.0;
    frag_color = vec4(shaded(n, visible), 1.0);
#endif
}
