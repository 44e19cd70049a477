#version 330 core
// Scene geometry in world coordinates (metres): tube, stripe, clamp, arrows, grid.
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 color;

uniform mat4 view_projection;

out vec3 world_position;
out vec3 world_normal;
out vec3 base_color;

void main()
{
    world_position = position;
    world_normal = normal;
    base_color = color;
    gl_Position = view_projection * vec4(position, 1.0);
}
