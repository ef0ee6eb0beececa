#version 330 core
// Smooth shading interpolates the vertex normals; flat shading looks up the
// polygon's normal (not the triangle's): triangle -> face through
// u_tri_face, face -> Newell normal through u_face_normal, both texture
// buffers indexed by gl_PrimitiveID (the triangle number within the draw).
// The UV checker (u_checker, with surface_uv.geom) replaces the base colour
// by a checker of 16 x 16 squares per unit of UV space, lit the same way,
// so the shape stays visible under the texture.
in vec3 v_pos;
in vec3 v_nrm;
in float v_shade;              // the sculpting mask darkens (1: unmasked)
in vec2 v_uv;

uniform mat4 u_view;
uniform int u_flat;
uniform usamplerBuffer u_tri_face;
uniform samplerBuffer u_face_normal;
uniform vec3 u_front;          // base colour of front faces
uniform vec3 u_back;           // base colour of back faces (inside of open meshes)
uniform int u_checker;

out vec4 o_color;

void main()
{
    vec3 n = v_nrm;
    if (u_flat != 0) {
        int f = int(texelFetch(u_tri_face, gl_PrimitiveID).r);
        n = mat3(u_view) * texelFetch(u_face_normal, f).xyz;
    }
    float len = length(n);
    n = len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
    vec3 base = u_front;
    if (!gl_FrontFacing) { n = -n; base = u_back; }
    if (u_checker != 0) {
        // Light squares, and dark ones tinted by where they are (red grows
        // with u, blue with v) so that flipped or rotated islands show.
        vec2 q = floor(v_uv * 16.0);
        vec2 f = fract(v_uv);
        vec3 dark = vec3(0.18 + 0.55 * f.x, 0.22, 0.18 + 0.55 * f.y);
        base = mod(q.x + q.y, 2.0) < 0.5 ? vec3(0.93, 0.93, 0.90) : dark;
        if (!gl_FrontFacing) base *= 0.6;
    }
    vec3 v = normalize(-v_pos);
    // A key light above left, a weaker fill from the right, a headlight
    // (surfaces facing the viewer never go dark) and a rim of sky.
#include "lighting.glsl.inc"
    o_color = vec4(clamp(c * v_shade, 0.0, 1.0), 1.0);
}
