#version 330 core
// Wide lines in a core profile (glLineWidth > 1 is not core): each segment
// becomes a screen-space quad u_width pixels wide.
layout(lines) in;
layout(triangle_strip, max_vertices = 4) out;

uniform vec2 u_viewport;       // pixels
uniform float u_width;         // pixels

void main()
{
    vec4 a = gl_in[0].gl_Position;
    vec4 b = gl_in[1].gl_Position;
    // Clip against the near plane so that w stays positive.
    if (a.w < 1e-6 && b.w < 1e-6) return;
    if (a.w < 1e-6) a = mix(a, b, (1e-6 - a.w) / (b.w - a.w));
    if (b.w < 1e-6) b = mix(b, a, (1e-6 - b.w) / (a.w - b.w));
    vec2 sa = a.xy / a.w * 0.5 * u_viewport;
    vec2 sb = b.xy / b.w * 0.5 * u_viewport;
    vec2 d = sb - sa;
    float len = length(d);
    vec2 dir = len > 0.0 ? d / len : vec2(1.0, 0.0);
    vec2 off = vec2(-dir.y, dir.x) * (0.5 * u_width) / (0.5 * u_viewport);
    gl_Position = vec4(a.xy + off * a.w, a.zw); EmitVertex();
    gl_Position = vec4(a.xy - off * a.w, a.zw); EmitVertex();
    gl_Position = vec4(b.xy + off * b.w, b.zw); EmitVertex();
    gl_Position = vec4(b.xy - off * b.w, b.zw); EmitVertex();
    EndPrimitive();
}
