#version 450 core
// Slicing pass, fragment stage: one pass writes colour (RGBA8, location 0) and the
// attribute record id (R32UI, location 1; never blended; 0 = background); the GS_BLOCKS
// variants also the block cell + 1 (R32UI, location 2; 0 = none), the cell whose class
// colours the fragment (caps of clipping bodies only, like the colour).
//
// uFaceRole, set per draw by renderer/slice_renderer.cpp:
//   0 exterior: a front face seen from outside; lit colour of uRecord.
//   1 cap: the fragment shows the interior of a body seen through the cut: a back face of
//     body X (the ray is inside X: cap of X), or a front face of a nested body whose
//     container was cut (the ray is inside the container). The CPU puts the right body's
//     record and colour into uCapRecord / uCapColour; drawn flat (unlit) like a cut face.
// uBaked = 1 (a GpuModel with an id texture): the record comes from T_ID (usampler2DArray,
// one layer per page, texelFetch = nearest) at the fragment's interpolated UV, as
// bake::fetchId() reads it on the CPU, and the colour from the record -> colour table.
// uFetch (per draw) says whether this fragment's own surface holds the record to show:
//   exterior faces and open surfaces: yes;
//   cap from a back face of body X: yes. The UV lies on X's far surface behind the cut, which
//     holds X's record in a per-body bake; with a grade field the cap shows the class of that
//     far surface point, not of the point on the cut plane (T_ID has no volume);
//   cap from a front face of a nested body D (the container's cut): no, D's texels hold D,
//     so the container's uCapRecord stays.
// A texel that holds no id (0: rounding at a chart border) falls back to the draw's record.
// GS_CLIP_DISTANCE = 0: the paper's pixel mask (eq. 5): discard when the plane test fails;
// uUnion = 1 keeps a fragment on the positive side of any plane, 0 of every plane.
// Two or more planes with uUnion = 0 keep a convex region K that a view ray can leave again
// while inside a body (a kept wedge or box seen through its apex): there no fragment of that
// body lies on the kept part of the ray, and the cap would be missing. So there a fragment
// is judged by where it lies on its view ray (from uEye): in front of K or on a ray that
// misses K, discarded; in K, as usual; beyond K ("past the exit"), kept as a witness of what
// the ray is inside where it leaves K: a cap (role 1) shows that body, as the nearest
// surviving fragment does with one plane; an exterior face or an open surface (role 0) means
// the ray left K in the open, so it writes the background (uBackground, id 0) at its depth.

in vec3 vLocal;
in vec2 vUv;

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
uniform int uBaked;
uniform int uFetch;
uniform vec4 uEye;         // local frame: the eye (w = 1, perspective) or the view direction (w = 0)
uniform vec4 uBackground;  // straight RGBA, for fragments past a convex cut's exit
layout(binding = 0) uniform usampler2DArray uIdTexture;
layout(binding = 1) uniform sampler2D uColourTable;  // record r at (r % width, r / width)

#if GS_BLOCKS
// Block-model colouring of caps (renderer/passes/block_texture.hpp): only in the GS_BLOCKS = 1
// variants, so that views without a block model do not pay for it (on llvmpipe the uniform
// branch alone cost ~29 % of a frame).
uniform vec3 uBlockOrigin;     // local frame
uniform vec3 uBlockToGrid[3];  // axis[a] / size[a]: local offset -> cell units
uniform ivec3 uBlockDims;
uniform vec4 uBlockColours[65];
uniform int uBlockClipCount;
// The clipping bodies' records, sorted, row by row (kBlockClipRow = 1024 per row).
layout(binding = 3) uniform usampler2D uBlockClip;
layout(binding = 2) uniform usampler3D uBlockClasses;  // 0 = no value, k + 1 = class k
#endif

layout(location = 0) out vec4 oColour;
layout(location = 1) out uint oRecord;
#if GS_BLOCKS
layout(location = 2) out uint oCell;  // BlockModel linear index + 1, 0 = none
#endif

// bake::fetchId(): layer floor(u), texel floor((u - layer) * W), floor(v * H); 0 outside.
uint fetchId(vec2 uv) {
    ivec3 size = textureSize(uIdTexture, 0);
    float page = floor(uv.x);
    ivec3 t = ivec3(ivec2(floor(vec2(uv.x - page, uv.y) * vec2(size.xy))), int(page));
    if (any(lessThan(t, ivec3(0))) || any(greaterThanEqual(t, size))) return 0u;
    return texelFetch(uIdTexture, t, 0).r;
}

#if GS_BLOCKS
// The colour of a cap fragment of `record` by the block cell at the point where its view ray
// crosses the cut: the entry into the kept region (intersection: the last plane crossed;
// union: the first), or `colour` when the record does not clip the block model, the point
// is outside the grid or its cell has no value. `cell`: the cell's linear index + 1
// (BlockModel::linear, i fastest), 0 when there is none (a cell with no value is a cell).
vec4 blockColour(uint record, vec4 colour, out uint cell) {
    cell = 0u;
    // Binary search of the sorted records.
    int lo = 0, hi = uBlockClipCount;
    bool clips = false;
    while (lo < hi && !clips) {
        int mid = (lo + hi) / 2;
        uint r = texelFetch(uBlockClip, ivec2(mid % 1024, mid / 1024), 0).r;
        clips = r == record;
        if (r < record) lo = mid + 1;
        else hi = mid;
    }
    if (!clips) return colour;
    vec3 dir = uEye.w != 0.0 ? normalize(vLocal - uEye.xyz) : uEye.xyz;
    float l = uUnion != 0 ? 3.0e38 : -3.0e38;
    bool crossed = false;
    for (int i = 0; i < uPlaneCount; ++i) {
        float ds = dot(uPlanes[i].xyz, dir);
        if (ds <= 0.0) continue;
        float li = -(dot(uPlanes[i].xyz, vLocal) + uPlanes[i].w) / ds;
        l = uUnion != 0 ? min(l, li) : max(l, li);
        crossed = true;
    }
    if (!crossed) return colour;
    vec3 d = vLocal + l * dir - uBlockOrigin;
    ivec3 c = ivec3(floor(vec3(dot(uBlockToGrid[0], d), dot(uBlockToGrid[1], d), dot(uBlockToGrid[2], d))));
    if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, uBlockDims))) return colour;
    cell = uint(c.x + uBlockDims.x * (c.y + uBlockDims.y * c.z)) + 1u;
    uint k = texelFetch(uBlockClasses, c, 0).r;
    return k == 0u ? colour : uBlockColours[k - 1u];
}
#endif

void main() {
    // Derivatives before any discard: they need the whole 2x2 quad alive.
    vec3 shown = vLocal * uShadeScale;
    vec3 n = normalize(cross(dFdx(shown), dFdy(shown)));
    bool pastExit = false;
#if !GS_CLIP_DISTANCE
    if (uPlaneCount > 1 && uUnion == 0) {
        // The view ray through this fragment: vLocal + l * dir, l < 0 towards the eye. K is
        // kept for l in [lo, hi]; the eye bounds lo in perspective.
        vec3 dir = uEye.w != 0.0 ? normalize(vLocal - uEye.xyz) : uEye.xyz;
        float lo = uEye.w != 0.0 ? -length(vLocal - uEye.xyz) : -3.0e38;
        float hi = 3.0e38;
        for (int i = 0; i < uPlaneCount; ++i) {
            float s = dot(uPlanes[i].xyz, vLocal) + uPlanes[i].w;
            float ds = dot(uPlanes[i].xyz, dir);
            if (ds > 0.0)
                lo = max(lo, -s / ds);
            else if (ds < 0.0)
                hi = min(hi, -s / ds);
            else if (s < 0.0)
                discard;
        }
        if (lo > hi || lo > 0.0) discard;
        pastExit = hi < 0.0;
    } else if (uPlaneCount > 0) {
        bool keep = uUnion == 0;
        for (int i = 0; i < uPlaneCount; ++i) {
            bool inside = dot(uPlanes[i].xyz, vLocal) + uPlanes[i].w >= 0.0;
            keep = uUnion != 0 ? (keep || inside) : (keep && inside);
        }
        if (!keep) discard;
    }
#endif
    uint record = uFaceRole == 1 ? uCapRecord : uRecord;
    vec4 colour = uFaceRole == 1 ? uCapColour : uColour;
    if (uBaked != 0) {
        uint id = 0u;
        if (uFetch != 0) id = fetchId(vUv);
        if (id != 0u) record = id;
        ivec2 table = textureSize(uColourTable, 0);
        ivec2 at = ivec2(int(record % uint(table.x)), int(record / uint(table.x)));
        if (at.y < table.y) colour = texelFetch(uColourTable, at, 0);
    }
#if GS_BLOCKS
    uint cell = 0u;
    if (uFaceRole == 1) colour = blockColour(record, colour, cell);
    oCell = cell;
#endif
    if (pastExit && uFaceRole != 1) {
        oRecord = 0u;
        oColour = uBackground;
        return;
    }
    oRecord = record;
    if (uFaceRole == 1) {
        oColour = colour;
    } else {
        float diffuse = abs(dot(n, uLightDir));
        oColour = vec4(colour.rgb * (0.35 + 0.65 * diffuse), colour.a);
    }
}
