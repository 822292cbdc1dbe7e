#!/usr/bin/env python3
"""Rewrites RINGMesh's geomodel3d.so (TVOLUME regions, each region listing its own vertices)
in the LightTSolid layout that OpenGeode's LSO writer (geode-solutions, lso_output.cpp, MIT)
and RINGMesh write: one VRTX per position, a SHAREDVRTX for the same position used again by
another region, TETRA lines with "# CTETRA <region> none none none none" comments, no
TVOLUME, then the MODEL section (SURFACE/TFACE/KEYVERTICES/TRGL on the VRTX ids) and the
file's own MODEL_REGION lines.

    python3 make_lightsolid.py geomodel3d.so lightsolid_ctetra.so lightsolid_model_region.so

The second output has no CTETRA comments: its regions are only the MODEL_REGION seeds.
"""
import sys


def main(src, out_ctetra, out_seeds):
    lines = open(src).read().splitlines()
    header, model = [], []
    pos_of = {}       # original id -> position key
    order = []        # original vertex ids in file order
    tets = []         # (region, [ids])
    region = None
    in_model = False
    header_done = False
    for line in lines:
        tok = line.split()
        if not tok:
            continue
        k = tok[0]
        if in_model:
            if k != "END":
                model.append(tok)
            continue
        if k in ("VRTX", "PVRTX"):
            pos_of[int(tok[1])] = (tok[2], tok[3], tok[4])
            order.append(int(tok[1]))
        elif k == "TVOLUME":
            region = " ".join(tok[1:])
        elif k == "TETRA":
            tets.append((region, [int(t) for t in tok[1:5]]))
        elif k == "MODEL":
            in_model = True
        elif k == "PROPERTIES":
            header_done = True
        elif k != "GOCAD" and not header_done:
            header.append(line)
    # One VRTX per position, for the first region that uses it; each other region using the
    # position gets its own SHAREDVRTX of it (as OpenGeode's writer does per block).
    vrtx_of_pos, new_id, shared = {}, {}, []
    for vid in order:
        if pos_of[vid] not in vrtx_of_pos:
            vrtx_of_pos[pos_of[vid]] = len(vrtx_of_pos) + 1
    first_region = {}
    for reg, ids in tets:
        for v in ids:
            first_region.setdefault(pos_of[v], reg)
    count = len(vrtx_of_pos)
    for reg, ids in tets:
        for v in ids:
            p = pos_of[v]
            if (reg, p) in new_id:
                continue
            if first_region[p] == reg:
                new_id[(reg, p)] = vrtx_of_pos[p]
            else:
                count += 1
                new_id[(reg, p)] = count
                shared.append((count, vrtx_of_pos[p]))
    unique = sorted(vrtx_of_pos.items(), key=lambda kv: kv[1])

    def write(path, ctetra):
        with open(path, "w") as f:
            f.write("GOCAD LightTSolid 1\n")
            for h in header:
                f.write(h + "\n")
            for p, n in unique:
                f.write("VRTX %d %s %s %s\n" % (n, p[0], p[1], p[2]))
            for n, ref in shared:
                f.write("SHAREDVRTX %d %d\n" % (n, ref))
            for reg, ids in tets:
                f.write("TETRA %s\n" % " ".join(str(new_id[(reg, pos_of[v])]) for v in ids))
                if ctetra:
                    f.write("# CTETRA %s none none none none\n" % reg)
            f.write("MODEL\n")
            for tok in model:
                if tok[0] in ("TRGL", "KEYVERTICES"):
                    f.write(tok[0] + " " + " ".join(str(vrtx_of_pos[pos_of[int(t)]]) for t in tok[1:4]) + "\n")
                else:
                    f.write(" ".join(tok) + "\n")
            f.write("END\n")

    write(out_ctetra, True)
    write(out_seeds, False)


if __name__ == "__main__":
    main(*sys.argv[1:4])
