#version 450 core
// Block-model cell pieces on the cut faces (renderer/passes/block_caps.hpp), fragment stage: writes
// the class colour (location 0; masked off for pieces of cells with no value) and the cell + 1
// (location 2) where the slicing pass drew a clipping body's cap (stencil test, set by the
// renderer). A piece of plane uPlane is where a view ray enters the kept region only if the
// ray crosses the plane towards its kept side and the point is on the kept region's boundary:
// every other plane keeps it (intersection) or removes it (uUnion = 1) - the rule of the
// caps' own shader (shaders/slice.frag blockColour) and of the fault traces.

in vec3 vLocal;
flat in uvec2 vCell;

uniform vec4 uPlanes[6];  // local frame, unit normals
uniform int uPlaneCount;
uniform int uPlane;
uniform int uUnion;
uniform vec4 uEye;  // local frame: the eye (w = 1, perspective) or the view direction (w = 0)
uniform vec4 uBlockColours[65];

layout(location = 0) out vec4 oColour;
layout(location = 2) out uint oCell;

void main() {
    vec3 dir = uEye.w != 0.0 ? normalize(vLocal - uEye.xyz) : uEye.xyz;
    if (dot(uPlanes[uPlane].xyz, dir) <= 0.0) discard;
    for (int i = 0; i < uPlaneCount; ++i) {
        if (i == uPlane) continue;
        bool kept = dot(uPlanes[i].xyz, vLocal) + uPlanes[i].w >= 0.0;
        if (kept == (uUnion != 0)) discard;
    }
    oColour = vCell.y == 0u ? vec4(0.0) : uBlockColours[vCell.y - 1u];
    oCell = vCell.x;
}
