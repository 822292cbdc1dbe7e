#!/usr/bin/env python3
"""Derives the categorical fill palette of model/style/palette.cpp (kFillPalette).

Greedy max-min selection over an sRGB grid: each next colour maximises its smallest
CIEDE2000 distance to the colours already chosen, measured in normal vision and under
protanopia and deuteranopia (Machado, Oliveira & Fernandes 2009, severity 1.0, applied in
linear RGB), so every prefix of the list is as spread as the greedy rule makes it. Fills are
kept light (CIELAB L* 55..92), neither grey nor garish (chroma 18..70) so that the dark line colours of
faults and surfaces (L* < 30) never look like a fill. Pure Python, deterministic:
    python3 scripts/make_palette.py 20
"""
import math
import sys

PROTAN = ((0.152286, 1.052583, -0.204868), (0.114503, 0.786281, 0.099216), (-0.003882, -0.048116, 1.051998))
DEUTAN = ((0.367322, 0.860646, -0.227968), (0.280085, 0.672501, 0.047413), (-0.011820, 0.042940, 0.968881))


def lin(c):
    c /= 255.0
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def lab_of_linear(r, g, b):
    r, g, b = (min(1.0, max(0.0, v)) for v in (r, g, b))
    x = 0.4124564 * r + 0.3575761 * g + 0.1804375 * b
    y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b
    z = 0.0193339 * r + 0.1191920 * g + 0.9503041 * b
    xn, yn, zn = 0.95047, 1.0, 1.08883

    def f(t):
        return t ** (1 / 3) if t > 216 / 24389 else (24389 / 27 * t + 16) / 116

    fx, fy, fz = f(x / xn), f(y / yn), f(z / zn)
    return 116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)


def views(rgb):
    r, g, b = (lin(v) for v in rgb)
    out = [lab_of_linear(r, g, b)]
    for m in (PROTAN, DEUTAN):
        out.append(lab_of_linear(*(m[i][0] * r + m[i][1] * g + m[i][2] * b for i in range(3))))
    return out


def de2000(l1, l2):
    L1, a1, b1 = l1
    L2, a2, b2 = l2
    c1, c2 = math.hypot(a1, b1), math.hypot(a2, b2)
    cm = (c1 + c2) / 2
    g = 0.5 * (1 - math.sqrt(cm ** 7 / (cm ** 7 + 25 ** 7)))
    a1p, a2p = (1 + g) * a1, (1 + g) * a2
    c1p, c2p = math.hypot(a1p, b1), math.hypot(a2p, b2)
    h1p = math.degrees(math.atan2(b1, a1p)) % 360 if c1p else 0.0
    h2p = math.degrees(math.atan2(b2, a2p)) % 360 if c2p else 0.0
    dl, dc = L2 - L1, c2p - c1p
    if c1p * c2p == 0:
        dh = 0.0
    else:
        dh = h2p - h1p
        if dh > 180:
            dh -= 360
        elif dh < -180:
            dh += 360
    dH = 2 * math.sqrt(c1p * c2p) * math.sin(math.radians(dh / 2))
    lm, cpm = (L1 + L2) / 2, (c1p + c2p) / 2
    if c1p * c2p == 0:
        hm = h1p + h2p
    elif abs(h1p - h2p) <= 180:
        hm = (h1p + h2p) / 2
    else:
        hm = (h1p + h2p + 360) / 2 if h1p + h2p < 360 else (h1p + h2p - 360) / 2
    t = (1 - 0.17 * math.cos(math.radians(hm - 30)) + 0.24 * math.cos(math.radians(2 * hm))
         + 0.32 * math.cos(math.radians(3 * hm + 6)) - 0.20 * math.cos(math.radians(4 * hm - 63)))
    dtheta = 30 * math.exp(-(((hm - 275) / 25) ** 2))
    rc = 2 * math.sqrt(cpm ** 7 / (cpm ** 7 + 25 ** 7))
    sl = 1 + 0.015 * (lm - 50) ** 2 / math.sqrt(20 + (lm - 50) ** 2)
    sc = 1 + 0.045 * cpm
    sh = 1 + 0.015 * cpm * t
    rt = -math.sin(math.radians(2 * dtheta)) * rc
    return math.sqrt((dl / sl) ** 2 + (dc / sc) ** 2 + (dH / sh) ** 2 + rt * (dc / sc) * (dH / sh))


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    levels = list(range(0, 256, 17))
    cands = []
    for r in levels:
        for g in levels:
            for b in levels:
                v = views((r, g, b))
                L, a, bb = v[0]
                if 55 <= L <= 92 and 18 <= math.hypot(a, bb) <= 70:
                    cands.append(((r, g, b), v))
    chosen = [min(cands, key=lambda c: abs(c[0][0] - 0xee) + abs(c[0][1] - 0x99) + abs(c[0][2] - 0x33))]
    best = {c[0]: min(de2000(c[1][k], chosen[0][1][k]) for k in range(3)) for c in cands}
    while len(chosen) < n:
        pick = max(cands, key=lambda c: (best[c[0]], c[0]))
        chosen.append(pick)
        for c in cands:
            d = min(de2000(c[1][k], pick[1][k]) for k in range(3))
            if d < best[c[0]]:
                best[c[0]] = d
    worst = min(min(de2000(a[1][k], b[1][k]) for k in range(3)) for i, a in enumerate(chosen) for b in chosen[:i])
    for c in chosen:
        print("    {0x%02x, 0x%02x, 0x%02x, 0xff}," % c[0])
    print("# min CIEDE2000 over normal/protan/deutan: %.2f" % worst, file=sys.stderr)


if __name__ == "__main__":
    main()
