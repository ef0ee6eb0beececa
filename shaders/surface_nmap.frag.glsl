#version 330 core
// The smooth shading of surface.frag.glsl (same lights and weights: keep the
// two in step) with the normal taken from a normal map: tangent space
// (n = T·m.x + B·m.y + N·m.z, B = w · N × T, the frame glTF and MikkTSpace
// define) or object space.
in vec3 v_pos;
in vec3 v_nrm;
in vec3 v_tan;
in float v_sign;
in vec2 v_uv;

uniform mat4 u_view;
uniform sampler2D u_map;
uniform int u_use_map;         // 0: vertex normals only
uniform int u_object_space;    // 1: the map holds object-space normals
uniform vec3 u_front;
uniform vec3 u_back;

out vec4 o_color;

void main()
{
    vec3 n = normalize(v_nrm);
    if (u_use_map != 0) {
        vec3 m = texture(u_map, v_uv).xyz * 2.0 - 1.0;
        if (u_object_space != 0) {
            n = mat3(u_view) * m;
        } else {
            vec3 t = v_tan - n * dot(n, v_tan);
            float tl = length(t);
            t = tl > 0.0 ? t / tl : vec3(1.0, 0.0, 0.0);
            vec3 b = v_sign * cross(n, t);
            n = m.x * t + m.y * b + m.z * n;
        }
    }
    float len = length(n);
    n = len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
    vec3 base = u_front;
    if (!gl_FrontFacing) { n = -n; base = u_back; }
    vec3 v = normalize(-v_pos);
#include "lighting.glsl.inc"
    o_color = vec4(clamp(c, 0.0, 1.0), 1.0);
}
