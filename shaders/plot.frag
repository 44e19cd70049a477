#version 330 core
// One flat colour per draw call; multisampling antialiases the edges.
uniform vec4 colour;

out vec4 fragment_colour;

void main()
{
    fragment_colour = colour;
}
