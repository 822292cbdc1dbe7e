#version 450 core
// Full-screen triangle for post passes: no vertex buffer (an empty vertex array is bound),
// three vertices from gl_VertexID covering clip space; vUv in [0, 1] over the viewport.

out vec2 vUv;

void main() {
    vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
    vUv = p * 0.5 + 0.5;
    gl_Position = vec4(p, 0.0, 1.0);
}
