#version 330 core
// Vertices of the control mesh, selected and hovered vertices.
layout(location = 0) in vec3 a_pos;

uniform mat4 u_view;
uniform mat4 u_proj;
uniform float u_size;          // pixels
uniform float u_depth_bias;

void main()
{
    vec4 p = u_proj * (u_view * vec4(a_pos, 1.0));
    p.z -= u_depth_bias * p.w;
    gl_Position = p;
    gl_PointSize = u_size;
}
