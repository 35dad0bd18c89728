#!/usr/bin/env python3
"""Writes a tower-like binary STL of about N triangles (default 1,000,000): a tapering
column of revolution 30 m tall with bulges (radius 4 m at the foot to 1.5 m at the
top, +-0.4 m), closed at the top, on a 10 x 10 x 1 m plinth; metres, z up. Plain
Python (struct), no numpy. For the mesh-input figures of benchmarks/README.md.

usage: tower_mesh.py OUT.stl [N]
"""
import math, struct, sys


def radius(z):
    return 4.0 - 2.5 * z / 30.0 + 0.4 * math.sin(0.8 * z)


def main():
    out, n = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 1_000_000
    rings = max(8, int(math.sqrt(n / 4)))   # height steps; azimuth steps = 2 x rings
    around = 2 * rings
    tris = []
    ring = lambda k: [(radius(1 + 29 * k / rings) * math.cos(2 * math.pi * j / around),
                       radius(1 + 29 * k / rings) * math.sin(2 * math.pi * j / around),
                       1 + 29 * k / rings) for j in range(around)]
    below = ring(0)
    for k in range(1, rings + 1):
        above = ring(k)
        for j in range(around):
            a, b, c, d = below[j], below[(j + 1) % around], above[(j + 1) % around], above[j]
            tris.append((a, b, c))
            tris.append((a, c, d))
        below = above
    top = (0.0, 0.0, 30.0)
    for j in range(around):
        tris.append((below[j], below[(j + 1) % around], top))
    lo, hi = (-5.0, -5.0, 0.0), (5.0, 5.0, 1.0)
    c = lambda i: (hi[0] if i & 1 else lo[0], hi[1] if i & 2 else lo[1], hi[2] if i & 4 else lo[2])
    for q in ((0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)):
        tris.append((c(q[0]), c(q[1]), c(q[2])))
        tris.append((c(q[0]), c(q[2]), c(q[3])))
    with open(out, "wb") as f:
        f.write(b"uavip tower".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        pack = struct.Struct("<12fH").pack
        for t in tris:
            f.write(pack(0.0, 0.0, 0.0, *t[0], *t[1], *t[2], 0))
    print("%s: %d triangles" % (out, len(tris)))


if __name__ == "__main__":
    main()
