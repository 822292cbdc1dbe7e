#!/usr/bin/python3
"""Writes box.str / box.dtm, a Surpac string file and DTM, by the public Surpac "String and
DTM files" record layout: run from this folder. (No program that writes Surpac files is
packaged in Debian; profile_5m_circle.str beside these is a real file written by Surpac.)

box.str: string 1 = the 8 corners of a 20 (x, easting) x 30 (y, northing) x 40 m box with its
  minimum corner at (500090.5, 7000185.5, 330): volume 24000 m3; string 2 = the 16 points of
  an open 3 x 3 grid (100 x 100 m at z = 300) in two segments (a separator record between
  them). Records are "string, Y, X, Z, description": Y (northing) first.
box.dtm: OBJECT 1 / TRISOLATION 1 = the box's 12 triangles (closed), OBJECT 2 /
  TRISOLATION 1 = the grid's 18 triangles (open); point numbers count the point records of
  box.str from 1 (separators not counted).
"""
QUADS = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (0, 4, 7, 3), (1, 2, 6, 5)]
x0, y0, z0 = 500090.5, 7000185.5, 330.0
box = [(x0, y0, z0), (x0 + 20, y0, z0), (x0 + 20, y0 + 30, z0), (x0, y0 + 30, z0),
       (x0, y0, z0 + 40), (x0 + 20, y0, z0 + 40), (x0 + 20, y0 + 30, z0 + 40), (x0, y0 + 30, z0 + 40)]
grid = [(500050.0 + 100.0 / 3 * i, 7000150.0 + 100.0 / 3 * j, 300.0) for j in range(4) for i in range(4)]

lines = ["box,28-Nov-26,geoslice test,ssi_styles:styles.ssi",
         "0,           0.000,           0.000,           0.000,           0.000,           0.000,           0.000"]
for (x, y, z) in box:
    lines.append("1, %.3f, %.3f, %.3f, corner" % (y, x, z))
lines.append("0, 0.000, 0.000, 0.000,")
for k, (x, y, z) in enumerate(grid):
    if k == 8:
        lines.append("0, 0.000, 0.000, 0.000,")
    lines.append("2, %.3f, %.3f, %.3f, " % (y, x, z))
lines.append("0, 0.000, 0.000, 0.000,")
lines.append("0, 0.000, 0.000, 0.000, END")
with open("box.str", "w") as f:
    f.write("\n".join(lines) + "\n")

out = ["box.str,28-Nov-26;algorithm=standard;fields=x,y", "0, 0.000, 0.000, 0.000, END",
       "OBJECT, 1,", "TRISOLATION, 1, neighbours=no,validated=true,closed=yes"]
t = 1
for a, b, c, d in QUADS:
    for tri in ((a, b, c), (a, c, d)):
        out.append("%d, %d, %d, %d, 0, 0, 0," % (t, tri[0] + 1, tri[1] + 1, tri[2] + 1))
        t += 1
out += ["OBJECT, 2,", "TRISOLATION, 1, neighbours=no,validated=true,closed=no"]
t = 1
for j in range(3):
    for i in range(3):
        p = 8 + j * 4 + i + 1  # 1-based point number of grid point (i, j)
        for tri in ((p, p + 1, p + 5), (p, p + 5, p + 4)):
            out.append("%d, %d, %d, %d, 0, 0, 0," % (t, tri[0], tri[1], tri[2]))
            t += 1
out.append("END")
with open("box.dtm", "w") as f:
    f.write("\n".join(out) + "\n")
