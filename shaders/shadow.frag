#version 330 core
// Depth only: the target has no colour buffer.
void main()
{
}
