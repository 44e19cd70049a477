#version 330 core
// Plot geometry in pixels (top-left origin, y down), already tessellated on the CPU.
layout(location = 0) in vec2 position_px;

uniform vec2 viewport_px;

void main()
{
    vec2 ndc = vec2(position_px.x / viewport_px.x * 2.0 - 1.0,
                    1.0 - position_px.y / viewport_px.y * 2.0);
    gl_Position = vec4(ndc, 0.0, 1.0);
}
