#version 330 core
// Surface: positions and per-vertex normals in object space.
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_nrm;
layout(location = 2) in float a_shade;   // sculpting mask: 1 - 0.6 mask (read only when u_masked)

uniform mat4 u_view;   // rigid (rotation + translation): mat3(u_view) turns normals
uniform mat4 u_proj;
uniform int u_masked;

out vec3 v_pos;        // view space
out vec3 v_nrm;        // view space, not normalised
out float v_shade;
out vec2 v_uv;         // texture coordinates: only surface_uv.geom has them

void main()
{
    vec4 p = u_view * vec4(a_pos, 1.0);
    v_pos = p.xyz;
    v_nrm = mat3(u_view) * a_nrm;
    v_shade = u_masked != 0 ? a_shade : 1.0;
    v_uv = vec2(0.0);
    gl_Position = u_proj * p;
}
