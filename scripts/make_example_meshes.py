#!/usr/bin/env python3
"""Writes the example obstacle meshes in examples/models/ (standard library only, deterministic).

    rock.obj      an icosphere (level 4: 5120 triangles) pushed in and out along its radii by a
                  smooth sum of sines: radius 1 +- 0.12, closed, outward
    armchair.obj  an armchair of welded boxes (seat, back, two arms, four legs): eight closed
                  components, about 1.6 m wide (units: metres, y up, facing +z)
    bowl.obj      a hemispherical bowl, open upwards: a shell between radii 0.9 and 1 below
                  y = 0, closed by its rim (1536 triangles), outward from the solid shell

Usage: scripts/make_example_meshes.py [OUT_DIR]   (default: examples/models next to this script)

Coordinates are written with 6 decimals so that the files do not depend on the last bits of
the platform's sin/cos; the same script gives the same bytes everywhere that rounds them alike.
"""
import math
import os
import sys


def icosphere(levels):
    """Vertices on the unit sphere and counter-clockwise (outward) triangles."""
    g = (1 + math.sqrt(5)) / 2
    raw = [(-1, g, 0), (1, g, 0), (-1, -g, 0), (1, -g, 0), (0, -1, g), (0, 1, g),
           (0, -1, -g), (0, 1, -g), (g, 0, -1), (g, 0, 1), (-g, 0, -1), (-g, 0, 1)]
    verts = [normalise(p) for p in raw]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        midpoint = {}

        def mid(i, j):
            key = (min(i, j), max(i, j))
            if key not in midpoint:
                a, b = verts[i], verts[j]
                midpoint[key] = len(verts)
                verts.append(normalise((a[0] + b[0], a[1] + b[1], a[2] + b[2])))
            return midpoint[key]

        finer = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            finer += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = finer
    return verts, faces


def normalise(p):
    n = math.sqrt(p[0] ** 2 + p[1] ** 2 + p[2] ** 2)
    return (p[0] / n, p[1] / n, p[2] / n)


def rock():
    """Radial bumps r(u) = 1 + sum a sin(k . u + phase) on unit directions u. Every vertex
    moves along its own radius by a positive factor, so each triangle's tetrahedron with the
    centre keeps its sign: the surface stays closed and outward (no fold)."""
    verts, faces = icosphere(4)
    waves = [(0.06, (2.1, 0.7, -1.3), 0.4), (0.04, (-0.9, 3.2, 1.7), 1.9),
             (0.02, (4.3, -2.6, 3.9), 2.7)]
    bumpy = []
    for u in verts:
        r = 1 + sum(a * math.sin(k[0] * u[0] + k[1] * u[1] + k[2] * u[2] + ph)
                    for a, k, ph in waves)
        bumpy.append((r * u[0], r * u[1], r * u[2]))
    # Flattened a little (y * 0.8): a rock, not a ball.
    bumpy = [(x, 0.8 * y, z) for x, y, z in bumpy]
    orient(bumpy, faces)
    return bumpy, faces


def orient(verts, faces):
    """Checks that every triangle faces away from the centre (the construction promises it)."""
    for a, b, c in faces:
        pa, pb, pc = verts[a], verts[b], verts[c]
        det = (pa[0] * (pb[1] * pc[2] - pb[2] * pc[1]) - pa[1] * (pb[0] * pc[2] - pb[2] * pc[0])
               + pa[2] * (pb[0] * pc[1] - pb[1] * pc[0]))
        assert det > 0, "inward triangle"


def box(verts, faces, lo, hi):
    """Appends the box [lo, hi] as 8 shared corners and 12 outward triangles."""
    base = len(verts)
    for i in range(8):  # corner i: bit 0 = x, bit 1 = y, bit 2 = z
        verts.append(tuple(hi[k] if i >> k & 1 else lo[k] for k in range(3)))
    quads = [(0, 2, 3, 1), (4, 5, 7, 6),  # z-, z+
             (0, 1, 5, 4), (2, 6, 7, 3),  # y-, y+
             (0, 4, 6, 2), (1, 3, 7, 5)]  # x-, x+
    for a, b, c, d in quads:
        faces.append((base + a, base + b, base + c))
        faces.append((base + a, base + c, base + d))


def armchair():
    verts, faces = [], []
    w, d = 0.8, 0.4  # half width (x) and half depth (z) of the seat
    leg = 0.06
    for sx in (-1, 1):
        for sz in (-1, 1):
            x, z = sx * (w - leg), sz * (d - leg)
            box(verts, faces, (x - leg, 0.0, z - leg), (x + leg, 0.40, z + leg))
    box(verts, faces, (-w, 0.40, -d), (w, 0.52, d))             # seat
    box(verts, faces, (-w, 0.52, -d), (w, 1.10, -d + 0.12))     # back
    for sx in (-1, 1):                                          # arms
        x0, x1 = (-w, -w + 0.12) if sx < 0 else (w - 0.12, w)
        box(verts, faces, (x0, 0.52, -d + 0.12), (x1, 0.75, d))
    return verts, faces


def bowl(around=48, rings=8, inner=0.9):
    """The lower half of a thick sphere shell: outer and inner surfaces from the bottom poles to
    the equator, joined by a flat rim. Normals point out of the solid (the inner surface's point
    towards the centre). Triangles are wound to face along those normals."""
    verts, faces = [], []

    def surface(radius):
        pole = len(verts)
        verts.append((0.0, -radius, 0.0))
        for i in range(1, rings + 1):
            phi = math.pi / 2 * i / rings  # from the bottom pole up to the equator
            for j in range(around):
                theta = 2 * math.pi * j / around
                verts.append((radius * math.sin(phi) * math.cos(theta), -radius * math.cos(phi),
                              radius * math.sin(phi) * math.sin(theta)))
        return pole

    def ring(pole, i, j):  # vertex j (mod around) of ring i (1 = next to the pole)
        return pole + 1 + (i - 1) * around + j % around

    outer, inner_pole = surface(1.0), surface(inner)
    for pole, out in ((outer, True), (inner_pole, False)):
        tris = []
        for j in range(around):
            tris.append((pole, ring(pole, 1, j + 1), ring(pole, 1, j)))
        for i in range(1, rings):
            for j in range(around):
                a, b = ring(pole, i, j), ring(pole, i, j + 1)
                c, d = ring(pole, i + 1, j + 1), ring(pole, i + 1, j)
                tris += [(a, b, c), (a, c, d)]
        # Wound outward for the outer surface; reversed for the inner one.
        faces += [(a, c, b) for a, b, c in tris] if out else tris
    for j in range(around):  # the rim at y = 0, facing up
        a, b = ring(outer, rings, j), ring(outer, rings, j + 1)
        c, d = ring(inner_pole, rings, j + 1), ring(inner_pole, rings, j)
        faces += [(a, c, b), (a, d, c)]
    check_facing(verts, faces, inner)
    return verts, faces


def check_facing(verts, faces, inner):
    """Each bowl triangle's normal points out of the shell: away from the centre on the outer
    surface, towards it on the inner one, up on the rim."""
    for a, b, c in faces:
        pa, pb, pc = verts[a], verts[b], verts[c]
        u = [pb[k] - pa[k] for k in range(3)]
        v = [pc[k] - pa[k] for k in range(3)]
        n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        centre = [(pa[k] + pb[k] + pc[k]) / 3 for k in range(3)]
        r = math.sqrt(sum(x * x for x in centre))
        radial = sum(n[k] * centre[k] for k in range(3))
        if all(abs(p[1]) < 1e-12 for p in (pa, pb, pc)):
            assert n[1] > 0, "rim triangle facing down"
        elif r > (1 + inner) / 2:
            assert radial > 0, "outer triangle facing in"
        else:
            assert radial < 0, "inner triangle facing out"


def write_obj(path, title, verts, faces):
    lines = [f"# {title}", f"# {len(verts)} vertices, {len(faces)} triangles; written by "
             "scripts/make_example_meshes.py"]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in verts]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    with open(path, "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "examples", "models")
    os.makedirs(out, exist_ok=True)
    v, f = rock()
    write_obj(os.path.join(out, "rock.obj"), "A rock: a bumpy icosphere, radius about 1", v, f)
    v, f = armchair()
    write_obj(os.path.join(out, "armchair.obj"), "An armchair of eight closed boxes (metres, y up)",
              v, f)
    v, f = bowl()
    write_obj(os.path.join(out, "bowl.obj"), "A bowl: a hemispherical shell, radii 0.9 to 1, open up",
              v, f)


if __name__ == "__main__":
    main()
