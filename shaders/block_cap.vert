#version 450 core
// Block-model cell pieces on the cut faces (renderer/passes/block_caps.hpp), vertex stage: one
// triangle of a cell's cut (a tetrahedron of the cell cut by a plane) per three vertices, in
// the model's local frame (world - origin, metres, float32), with its cell and class.

layout(location = 0) in vec3 aPosition;
layout(location = 1) in uvec2 aCell;  // (BlockModel linear index + 1, class: 0 = no value, k + 1 = class k)

uniform mat4 uViewProj;

out vec3 vLocal;
flat out uvec2 vCell;

void main() {
    vLocal = aPosition;
    vCell = aCell;
    gl_Position = uViewProj * vec4(aPosition, 1.0);
}
