#version 450 core
// Slicing pass, vertex stage. Positions are in the model's local frame (world - origin,
// metres, float32); uViewProj maps local -> clip. Planes are in the local frame too
// (converted from world in double on the CPU): a point p is kept when dot(xyz, p) + w >= 0.
// GS_CLIP_DISTANCE = 1: planes go to gl_ClipDistance (intersection mode only: every enabled
// distance must be >= 0). GS_CLIP_DISTANCE = 0: the fragment stage discards (paper eq. 5).

layout(location = 0) in vec3 aPosition;

uniform mat4 uViewProj;
uniform vec4 uPlanes[6];
uniform int uPlaneCount;

out gl_PerVertex {
    vec4 gl_Position;
    float gl_ClipDistance[6];
};
out vec3 vLocal;

void main() {
    vLocal = aPosition;
    gl_Position = uViewProj * vec4(aPosition, 1.0);
#if GS_CLIP_DISTANCE
    for (int i = 0; i < 6; ++i)
        gl_ClipDistance[i] = i < uPlaneCount ? dot(uPlanes[i].xyz, aPosition) + uPlanes[i].w : 1.0;
#endif
}
