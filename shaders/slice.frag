#version 450 core
// Slicing pass, fragment stage: one pass writes colour (RGBA8, location 0) and the
// attribute record id (R32UI, location 1; never blended; 0 = background).
//
// uFaceRole, set per draw by renderer/slice_renderer.cpp:
//   0 exterior: a front face seen from outside; lit colour of uRecord.
//   1 cap: the fragment shows the interior of a body seen through the cut: a back face of
//     body X (the ray is inside X: cap of X), or a front face of a nested body whose
//     container was cut (the ray is inside the container). The CPU puts the right body's
//     record and colour into uCapRecord / uCapColour; drawn flat (unlit) like a cut face.
// GS_CLIP_DISTANCE = 0: the paper's pixel mask (eq. 5): discard when the plane test fails;
// uUnion = 1 keeps a fragment on the positive side of any plane, 0 of every plane.

in vec3 vLocal;

uniform vec4 uPlanes[6];
uniform int uPlaneCount;
uniform int uUnion;
uniform int uFaceRole;
uniform uint uRecord;
uniform vec4 uColour;
uniform uint uCapRecord;
uniform vec4 uCapColour;
uniform vec3 uLightDir;  // local frame, unit, towards the light
uniform vec3 uShadeScale;  // (1, 1, vertical exaggeration): shade the surface as displayed

layout(location = 0) out vec4 oColour;
layout(location = 1) out uint oRecord;

void main() {
    // Derivatives before any discard: they need the whole 2x2 quad alive.
    vec3 shown = vLocal * uShadeScale;
    vec3 n = normalize(cross(dFdx(shown), dFdy(shown)));
#if !GS_CLIP_DISTANCE
    if (uPlaneCount > 0) {
        bool keep = uUnion == 0;
        for (int i = 0; i < uPlaneCount; ++i) {
            bool inside = dot(uPlanes[i].xyz, vLocal) + uPlanes[i].w >= 0.0;
            keep = uUnion != 0 ? (keep || inside) : (keep && inside);
        }
        if (!keep) discard;
    }
#endif
    if (uFaceRole == 1) {
        oRecord = uCapRecord;
        oColour = uCapColour;
    } else {
        float diffuse = abs(dot(n, uLightDir));
        oRecord = uRecord;
        oColour = vec4(uColour.rgb * (0.35 + 0.65 * diffuse), uColour.a);
    }
}
