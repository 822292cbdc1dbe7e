#version 450 core
// Cheap anti-aliasing of the colour output for CPU rasterisers (llvmpipe), in the spirit of
// Lottes' FXAA (2009): find pixels whose 3x3 luma contrast is high, estimate the edge
// direction from the four diagonal neighbours, and average two or four bilinear taps along
// that edge; keep the four-tap result unless it leaves the local luma range. Colour only:
// the ID buffer is a separate attachment that this pass never reads or writes.
// Straight alpha in and out; taps are averaged premultiplied, so transparent background
// does not darken the edge of the section.

in vec2 vUv;

uniform sampler2D uColour;  // the slicing pass's RGBA8 colour, bilinear, clamped
uniform vec2 uTexel;        // 1 / size in pixels

layout(location = 0) out vec4 oColour;

const float kEdgeMin = 1.0 / 16.0;  // contrast below this (absolute luma) is left alone
const float kReduceMul = 1.0 / 8.0;
const float kReduceMin = 1.0 / 128.0;
const float kSpanMax = 8.0;  // pixels

vec4 premul(vec4 c) { return vec4(c.rgb * c.a, c.a); }
vec4 tap(vec2 uv) { return premul(texture(uColour, uv)); }
// The 3x3 taps sit on texel centres: an unfiltered fetch is enough and cheaper on llvmpipe.
vec4 fetch(ivec2 p) { return premul(texelFetch(uColour, clamp(p, ivec2(0), textureSize(uColour, 0) - 1), 0)); }
float luma(vec4 p) { return dot(p.rgb, vec3(0.299, 0.587, 0.114)) + 0.25 * p.a; }

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 m = fetch(p);
    vec4 nw = fetch(p + ivec2(-1, -1)), ne = fetch(p + ivec2(1, -1));
    vec4 sw = fetch(p + ivec2(-1, 1)), se = fetch(p + ivec2(1, 1));
    float lm = luma(m), lnw = luma(nw), lne = luma(ne), lsw = luma(sw), lse = luma(se);
    float lo = min(lm, min(min(lnw, lne), min(lsw, lse)));
    float hi = max(lm, max(max(lnw, lne), max(lsw, lse)));
    vec4 result = m;
    if (hi - lo >= kEdgeMin) {
        vec2 dir = vec2(-((lnw + lne) - (lsw + lse)), (lnw + lsw) - (lne + lse));
        float reduce = max((lnw + lne + lsw + lse) * (0.25 * kReduceMul), kReduceMin);
        float scale = 1.0 / (min(abs(dir.x), abs(dir.y)) + reduce);
        dir = clamp(dir * scale, vec2(-kSpanMax), vec2(kSpanMax)) * uTexel;
        vec4 a = 0.5 * (tap(vUv + dir * (1.0 / 3.0 - 0.5)) + tap(vUv + dir * (2.0 / 3.0 - 0.5)));
        vec4 b = 0.5 * a + 0.25 * (tap(vUv - 0.5 * dir) + tap(vUv + 0.5 * dir));
        float lb = luma(b);
        result = (lb < lo || lb > hi) ? a : b;
    }
    oColour = result.a > 0.0 ? vec4(result.rgb / result.a, result.a) : vec4(0.0);
}
