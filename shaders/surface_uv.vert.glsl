#version 330 core
// Surface in UV checker mode: surface.vert's outputs, handed to
// surface_uv.geom (which adds the corners' texture coordinates).
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_nrm;
layout(location = 2) in float a_shade;

uniform mat4 u_view;
uniform mat4 u_proj;
uniform int u_masked;

out vec3 g_pos;
out vec3 g_nrm;
out float g_shade;

void main()
{
    vec4 p = u_view * vec4(a_pos, 1.0);
    g_pos = p.xyz;
    g_nrm = mat3(u_view) * a_nrm;
    g_shade = u_masked != 0 ? a_shade : 1.0;
    gl_Position = u_proj * p;
}
