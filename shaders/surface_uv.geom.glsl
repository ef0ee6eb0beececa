#version 330 core
// Face-varying UVs: a vertex on a UV seam has another texture coordinate in
// each face, so UVs cannot ride on the shared vertex buffer.  They come per
// triangle corner from u_tri_uv (RG32F, 3 texels per triangle, in the order
// of the triangle's indices), fetched by the triangle number; positions and
// normals stay in the vertex buffer that edits refresh in place.
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

in vec3 g_pos[];
in vec3 g_nrm[];
in float g_shade[];

uniform samplerBuffer u_tri_uv;

out vec3 v_pos;
out vec3 v_nrm;
out float v_shade;
out vec2 v_uv;

void main()
{
    for (int k = 0; k < 3; k++) {
        gl_Position = gl_in[k].gl_Position;
        v_pos = g_pos[k];
        v_nrm = g_nrm[k];
        v_shade = g_shade[k];
        v_uv = texelFetch(u_tri_uv, 3 * gl_PrimitiveIDIn + k).xy;
        gl_PrimitiveID = gl_PrimitiveIDIn;   // flat shading's lookups in surface.frag
        EmitVertex();
    }
    EndPrimitive();
}
