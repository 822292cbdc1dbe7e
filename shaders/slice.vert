#version 450 core
// Slicing pass, vertex stage. Positions are in the model's local frame (world - origin,
// metres, float32); uViewProj maps local -> clip. Planes are in the local frame too
// (converted from world in double on the CPU): a point p is kept when dot(xyz, p) + w >= 0.
// GS_CLIP_DISTANCE = 1: planes go to gl_ClipDistance (intersection mode only: every enabled
// distance must be >= 0). GS_CLIP_DISTANCE = 0: the fragment stage discards (paper eq. 5).

layout(location = 0) in vec3 aPosition;
// Baked models only (renderer/gpu_model.hpp): texture coordinate "page + u, v" of T_ID.
layout(location = 1) in vec2 aUv;

uniform mat4 uViewProj;
uniform vec4 uPlanes[6];
uniform int uPlaneCount;
// Level of detail (renderer/gpu_model.hpp): a simplified cluster deviates from the true
// surface by at most its error e. It is drawn moved along the view ray by uLodShift metres
// (local frame): back faces towards the viewer (-), front faces away (+), so that where a
// body's back face and its neighbour's front face coincide (shared horizons) the back face
// still wins, as it does at full detail. uEye: the eye (w = 1, perspective) or the view
// direction (w = 0, orthographic), local frame. Clip distances use the true position.
uniform vec4 uEye;
uniform float uLodShift;
// Rasterizer snapping (docs/design/renderer.md, "Coverage and depth from one position"): the
// rasterizer decides coverage from window positions snapped to 1 / 2^GL_SUBPIXEL_BITS of a
// pixel, but llvmpipe interpolates depth from the unsnapped float positions. Where a contact
// folds as seen along the ray (its two triangles on one side of their shared edge in the
// image, the order of their depths swapping across it), a pixel centre within the snap of
// the edge was covered as on one side and given the depths of the other; with grazing
// triangles that is metres of depth, and the wrong body's back face won kilometres inside a
// formation. Snapping here, to the same grid, gives coverage and depth one position.
// uSnap = (image width, height, grid steps per pixel; 0 = no snapping).
uniform vec3 uSnap;

out gl_PerVertex {
    vec4 gl_Position;
    float gl_ClipDistance[6];
};
out vec3 vLocal;
out vec2 vUv;

// The clip-space xy whose window position is the grid point nearest to the vertex's. Left
// alone: vertices at or behind the eye (w <= 0; the clipper makes new ones) and so far outside
// the image that the count of grid steps passes 2^23 (float stops holding every step).
vec2 snapToSubpixels(vec4 clip) {
    if (uSnap.z <= 0.0 || clip.w <= 0.0) return clip.xy;
    vec2 steps = (clip.xy / clip.w * 0.5 + 0.5) * uSnap.xy * uSnap.z;
    if (any(greaterThanEqual(abs(steps), vec2(8388608.0)))) return clip.xy;
    return (round(steps) / uSnap.z / uSnap.xy * 2.0 - 1.0) * clip.w;
}

void main() {
    vLocal = aPosition;
    vUv = aUv;
    vec3 ray = uEye.w != 0.0 ? aPosition - uEye.xyz : uEye.xyz;
    vec3 shown = aPosition + (uLodShift != 0.0 ? normalize(ray) * uLodShift : vec3(0.0));
    gl_Position = uViewProj * vec4(shown, 1.0);
    gl_Position.xy = snapToSubpixels(gl_Position);
#if GS_CLIP_DISTANCE
    for (int i = 0; i < 6; ++i)
        gl_ClipDistance[i] = i < uPlaneCount ? dot(uPlanes[i].xyz, aPosition) + uPlanes[i].w : 1.0;
#endif
}
