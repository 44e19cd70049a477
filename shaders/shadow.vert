#version 330 core
// The shadow map's depth pass: the casters seen from the key light.
layout(location = 0) in vec3 position;

uniform mat4 light_view_projection;

void main()
{
    gl_Position = light_view_projection * vec4(position, 1.0);
}
