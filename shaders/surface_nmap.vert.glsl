#version 330 core
// Surface with a normal map (render/nmap.h): positions, vertex normals,
// glTF-style tangents (xyz, bitangent sign w) and UVs per triangle corner.
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_nrm;
layout(location = 2) in vec4 a_tan;
layout(location = 3) in vec2 a_uv;

uniform mat4 u_view;   // rigid: mat3(u_view) turns normals and tangents
uniform mat4 u_proj;

out vec3 v_pos;        // view space
out vec3 v_nrm;        // view space, not normalised
out vec3 v_tan;        // view space, not normalised
out float v_sign;
out vec2 v_uv;

void main()
{
    vec4 p = u_view * vec4(a_pos, 1.0);
    v_pos = p.xyz;
    v_nrm = mat3(u_view) * a_nrm;
    v_tan = mat3(u_view) * a_tan.xyz;
    v_sign = a_tan.w;
    v_uv = a_uv;
    gl_Position = u_proj * p;
}
