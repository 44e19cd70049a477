#version 330 core
// Blinn-Phong with a key and a fill light (directional), plus ambient.
in vec3 world_position;
in vec3 world_normal;
in vec3 base_color;

uniform int lit;              // 0: flat colour (grid lines)
uniform int orthographic;     // 1: the eye direction is the same everywhere
uniform vec3 eye;             // world position of the camera (perspective)
uniform vec3 view_direction;  // unit, from the scene towards the eye (orthographic)
uniform vec3 key_direction;   // unit, towards the key light
uniform vec3 fill_direction;  // unit, towards the fill light

out vec4 frag_color;

void main()
{
    if (lit == 0) {
        frag_color = vec4(base_color, 1.0);
        return;
    }
    vec3 n = normalize(world_normal);
    vec3 v = orthographic == 1 ? view_direction : normalize(eye - world_position);
    if (dot(n, v) < 0.0) n = -n;  // two-sided: caps and ribbons seen from behind
    float key_diffuse = max(dot(n, key_direction), 0.0);
    float fill_diffuse = max(dot(n, fill_direction), 0.0);
    vec3 h = normalize(key_direction + v);
    float specular = pow(max(dot(n, h), 0.0), 48.0) * (key_diffuse > 0.0 ? 1.0 : 0.0);
    vec3 c = base_color * (0.22 + 0.78 * key_diffuse + 0.30 * fill_diffuse) + vec3(0.35 * specular);
    frag_color = vec4(min(c, vec3(1.0)), 1.0);
}
