#version 450 core
// Fault traces: line segments where open surfaces cross a cut plane, computed on the CPU in
// the local frame (renderer/slice_renderer.cpp). uViewProj maps local -> clip (vertical
// exaggeration included). No clip distances: the segments lie on the planes themselves.

layout(location = 0) in vec3 aPosition;

uniform mat4 uViewProj;

void main() { gl_Position = uViewProj * vec4(aPosition, 1.0); }
