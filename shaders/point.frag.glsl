#version 330 core
// Round points with a dark outline.
uniform vec4 u_color;
out vec4 o_color;

void main()
{
    vec2 q = gl_PointCoord * 2.0 - 1.0;
    float r = dot(q, q);
    if (r > 1.0) discard;
    o_color = r > 0.55 ? vec4(u_color.rgb * 0.35, u_color.a) : u_color;
}
