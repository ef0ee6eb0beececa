#version 330 core
// Lines (polygon edges, control mesh, interest box), widened by line.geom.
layout(location = 0) in vec3 a_pos;

uniform mat4 u_view;
uniform mat4 u_proj;
uniform float u_depth_bias;    // pulls lines toward the eye (fraction of w)

void main()
{
    vec4 p = u_proj * (u_view * vec4(a_pos, 1.0));
    p.z -= u_depth_bias * p.w;
    gl_Position = p;
}
