#!/usr/bin/env python3
"""Writes strand hair test data as Cem Yuksel's cyHair .hair files: fur over
a body, a sparse set lying on a scalp, a long straight curtain and curls.
Python 3 standard library only; deterministic: the same arguments and --seed
give the same bytes.

usage: gen-strands.py KIND -o OUT.hair [options]

KIND:
  fur       short strands of --points points (default 30000 x 4) rooted on
            an ellipsoid body (semi-axes 1.6R, R, R), leaving the surface at
            a low angle and lying along a combed direction field (tail-wards
            and down, with slow swirls), like a TressFX fur asset; length
            about 7% of R, +-25%
  sparse    few strands (default 150, 4-20 segments each, like
            ../shared/data/hair/Bangs_100.hair) rooted over the upper scalp
            and lying on it, swept across the head, lengths 0.15R-2.4R
  straight  a curtain of long straight, nearly parallel strands (default
            4000 x 16 points) hanging from a band 2.4R wide, length 2.5R
  curls     helical strands (default 3000 x 48 points, 2.5-4 turns of
            radius 0.05R-0.08R) around axes that leave the upper scalp and
            fall over it under gravity

The frame is the satf scene's: y up, the scalp a sphere of radius R at the
origin with the face towards +z. R defaults to 31, the scalp radius of the
shared ponytail (../shared/data/hair/ponytail_*.tfx: its roots lie on a
sphere of radius 30.9), so generated hair has the shared data's units.

options:
  -o, --output PATH      the .hair file to write (required)
  --strands N            strand count (default: per KIND, above)
  --points N             points per strand (default: per KIND; sparse
                         draws 5-21 per strand unless given)
  --radius R             scalp / body radius (default 31)
  --length L             strand length (default: per KIND, above)
  --thickness D          strand diameter at the root, written as the
                         header's default thickness (default: a hair
                         fibre, 1e-3 of the strands' bounding-box
                         diagonal, as satf-import's default width and
                         the Cycles reference's; sparse 0.3)
  --per-point-thickness  also write the per-point thickness array: D at the
                         root tapering linearly to D * TAPER at the tip
  --taper F              tip thickness over root thickness (default 0.3)
  --seed N               random seed (default 1)
  -q, --quiet            print nothing
  -h, --help             this help

The file: a 128-byte header ("HAIR", u32 strands, u32 points, u32 array
flags = 1 segments | 2 points [| 4 thickness], u32 default segments, f32
default thickness, f32 default transparency, f32[3] default colour,
char[88] info), then u16 segments[strands], f32 points[3 * points] and
f32 thickness[points] if present, little-endian; written to OUT.tmp-PID and
renamed into place.
"""
import argparse
import math
import os
import random
import struct
import sys
from array import array

DEFAULTS = {  # strands, points per strand
    "fur": (30000, 4),
    "sparse": (150, None),
    "straight": (4000, 16),
    "curls": (3000, 48),
}


# ---- small vector helpers (tuples of three floats) -------------------------

def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def mul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(dot(a, a))


def unit(a, fallback=(1.0, 0.0, 0.0)):
    n = norm(a)
    return mul(a, 1.0 / n) if n > 1e-12 else fallback


def tangent_part(v, n):
    """v with its component along the unit normal n removed."""
    return sub(v, mul(n, dot(v, n)))


def any_perpendicular(n):
    a = (1.0, 0.0, 0.0) if abs(n[0]) < 0.9 else (0.0, 1.0, 0.0)
    return unit(cross(n, a))


def sphere_point(rng):
    """Uniform on the unit sphere."""
    y = rng.uniform(-1.0, 1.0)
    phi = rng.uniform(0.0, 2.0 * math.pi)
    s = math.sqrt(max(0.0, 1.0 - y * y))
    return (s * math.cos(phi), y, s * math.sin(phi))


# ---- strand shapes ---------------------------------------------------------

def fur(rng, n, pts, R, length):
    """Roots uniform by area on an ellipsoid (rejection on the area element
    of the sphere-to-ellipsoid map); each strand leaves the surface 15-35
    degrees above the tangent plane along a combed direction and bends
    towards the surface, with a little per-point noise."""
    ax = (1.6 * R, R, R)
    # area element of p = (a x, b y, c z) over the unit sphere point (x,y,z)
    bound = max(ax[1] * ax[2], ax[0] * ax[2], ax[0] * ax[1])
    comb = unit((-1.0, -0.45, 0.0))  # towards the tail (-x) and down
    strands = []
    while len(strands) < n:
        u = sphere_point(rng)
        area = math.sqrt((ax[1] * ax[2] * u[0]) ** 2 + (ax[0] * ax[2] * u[1]) ** 2
                         + (ax[0] * ax[1] * u[2]) ** 2)
        if rng.random() * bound > area:
            continue
        root = (ax[0] * u[0], ax[1] * u[1], ax[2] * u[2])
        normal = unit((u[0] / ax[0], u[1] / ax[1], u[2] / ax[2]))
        # slow swirls: the comb turned about the normal by a smooth field
        swirl = 0.6 * math.sin(root[0] * 0.11 + 1.3 * math.sin(root[1] * 0.07)) \
            + 0.4 * math.sin(root[2] * 0.09 + root[1] * 0.05)
        t = tangent_part(comb, normal)
        if norm(t) < 0.2:  # where the comb meets the surface head-on
            t = tangent_part((0.0, -1.0, 0.0), normal)
        t = unit(t, any_perpendicular(normal))
        b = cross(normal, t)
        t = unit(add(mul(t, math.cos(swirl)), mul(b, math.sin(swirl))))
        lift = math.radians(rng.uniform(15.0, 35.0))
        L = length * rng.uniform(0.75, 1.25)
        step = L / (pts - 1)
        p, out = root, [root]
        for k in range(1, pts):
            a = lift * (1.0 - 0.6 * k / (pts - 1))  # bends towards the skin
            d = add(mul(t, math.cos(a)), mul(normal, math.sin(a)))
            jitter = (rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1))
            p = add(add(p, mul(d, step)), mul(jitter, 0.06 * step))
            out.append(p)
        strands.append(out)
    return strands


def drape(rng, root, start, length, pts, clearance, gravity, wander,
          cling=0.0):
    """A curve from root: it leaves along the unit direction start, is
    pulled by gravity (per unit length) and wanders, and never enters the
    sphere of radius clearance at the origin: a step that would is
    projected back onto it and its direction onto the tangent plane, so the
    strand lies over the scalp. Outside that sphere and above the ear line
    (y > -0.2 clearance), cling bends it towards the centre by that
    fraction of the curvature that follows the sphere (1: it wraps around
    the scalp along a great circle)."""
    fine = max(4 * (pts - 1), 64)
    step = length / fine
    d = start
    p, curve = root, [root]
    for _ in range(fine):
        r = norm(p)
        pull = cling * step / r if p[1] > -0.2 * clearance else 0.0
        d = unit(add(add(d, mul(p, -pull / r)),
                     (rng.gauss(0, wander) * step, -gravity * step,
                      rng.gauss(0, wander) * step)))
        q = add(p, mul(d, step))
        r = norm(q)
        if r < clearance:
            n = mul(q, 1.0 / r)
            q = mul(n, clearance)
            d = unit(tangent_part(d, n), any_perpendicular(n))
        curve.append(q)
        p = q
    return curve


def resample(curve, pts):
    """pts points evenly spaced in arc length along the polyline curve."""
    acc = [0.0]
    for a, b in zip(curve, curve[1:]):
        acc.append(acc[-1] + norm(sub(b, a)))
    out, j = [], 0
    for k in range(pts):
        s = acc[-1] * k / (pts - 1)
        while j < len(curve) - 2 and acc[j + 1] < s:
            j += 1
        span = acc[j + 1] - acc[j]
        f = (s - acc[j]) / span if span > 0 else 0.0
        out.append(add(curve[j], mul(sub(curve[j + 1], curve[j]), f)))
    return out


def cap_root(rng, R, max_polar, centre):
    """Uniform on the cap of the radius-R sphere within max_polar radians
    of the unit direction centre."""
    cos_max = math.cos(max_polar)
    c = rng.uniform(cos_max, 1.0)
    phi = rng.uniform(0.0, 2.0 * math.pi)
    s = math.sqrt(max(0.0, 1.0 - c * c))
    e1 = any_perpendicular(centre)
    e2 = cross(centre, e1)
    n = add(mul(centre, c), add(mul(e1, s * math.cos(phi)),
                                mul(e2, s * math.sin(phi))))
    n = unit(n)
    return mul(n, R), n


def sparse(rng, n, pts, R, length):
    """Like Bangs_100: roots over the upper scalp (a cap of 80 degrees
    around a point above the -x side), each strand swept across the head
    towards +x and a little down, 5-15 degrees off the scalp and then lying
    on it (clearance 1.02R-1.06R, weak gravity, some wander), of very
    different lengths and point counts."""
    cap = unit((-0.45, 1.0, 0.0))
    strands = []
    for _ in range(n):
        root, normal = cap_root(rng, R * 1.005, math.radians(80.0), cap)
        sweep = (1.0 + rng.gauss(0, 0.3), -0.35 + rng.gauss(0, 0.3),
                 rng.gauss(0, 0.35))
        t = unit(tangent_part(sweep, normal), any_perpendicular(normal))
        up = math.radians(rng.uniform(5.0, 15.0))
        start = add(mul(t, math.cos(up)), mul(normal, math.sin(up)))
        L = length * math.exp(rng.uniform(math.log(0.15), math.log(2.4)))
        k = pts if pts else rng.randint(5, 21)
        curve = drape(rng, root, start, L, k, R * rng.uniform(1.02, 1.06),
                      gravity=0.4 / R, wander=1.2 / R, cling=1.0)
        strands.append(resample(curve, k))
    return strands


def straight(rng, n, pts, R, length):
    """A curtain: roots on a horizontal band 2.4R wide and 0.1R deep at
    height R, each strand straight down with a small random lean (about 1
    degree) and a faint sway, so neighbours stay nearly parallel."""
    strands = []
    for _ in range(n):
        root = (rng.uniform(-1.2, 1.2) * R, R + rng.gauss(0, 0.01 * R),
                rng.uniform(-0.05, 0.05) * R)
        lean = (rng.gauss(0, 0.018), rng.gauss(0, 0.018))
        sway = rng.uniform(0.0, 2.0 * math.pi)
        L = length * rng.uniform(0.93, 1.0)
        out = []
        for k in range(pts):
            s = L * k / (pts - 1)
            out.append((root[0] + lean[0] * s
                        + 0.01 * R * math.sin(sway + 3.0 * s / L) * s / L,
                        root[1] - s, root[2] + lean[1] * s))
        strands.append(out)
    return strands


def curls(rng, n, pts, R, length):
    """Helices of 2.5-4 turns and radius 0.05R-0.08R around draped axes
    rooted on the upper scalp; the helix radius grows from 0 over the first
    10% so every strand starts at its root. Frames are parallel-transported
    along the axis, so the coil does not twist about it."""
    top = (0.0, 1.0, 0.0)
    strands = []
    for _ in range(n):
        root, normal = cap_root(rng, R * 1.005, math.radians(75.0), top)
        L = length * rng.uniform(0.8, 1.2)
        axis = drape(rng, root, normal, L, pts, R * 1.06,
                     gravity=1.2 / R, wander=0.5 / R)
        axis = resample(axis, 8 * pts)
        turns = rng.uniform(2.5, 4.0)
        rad = R * rng.uniform(0.05, 0.08)
        phase = rng.uniform(0.0, 2.0 * math.pi)
        hand = 1.0 if rng.random() < 0.5 else -1.0
        t = unit(sub(axis[1], axis[0]))
        nrm = any_perpendicular(t)
        helix = []
        for k, a in enumerate(axis):
            if k > 0:
                t_new = unit(sub(a, axis[k - 1]), t)
                nrm = unit(tangent_part(nrm, t_new), any_perpendicular(t_new))
                t = t_new
            bin_ = cross(t, nrm)
            f = k / (len(axis) - 1)
            ang = phase + hand * 2.0 * math.pi * turns * f
            r = rad * min(1.0, f / 0.1)
            helix.append(add(a, add(mul(nrm, r * math.cos(ang)),
                                    mul(bin_, r * math.sin(ang)))))
        strands.append(resample(helix, pts))
    return strands


KINDS = {"fur": fur, "sparse": sparse, "straight": straight, "curls": curls}
LENGTHS = {"fur": 0.07, "sparse": 0.8, "straight": 2.5, "curls": 1.3}
# Root diameters. Fur, straight hair and curls default to a hair fibre: 1e-3
# of the strands' bounding-box diagonal, the width satf-import gives strands
# whose file sets none and the radius (5e-4 of the diagonal) at which
# ../shared/tools/peer_cycles.py renders the Cycles reference, so both draw
# the same fibres. (Written as a fixed 0.1, the curls were drawn 0.70 times
# the reference's width and covered 0.92 of its pixels: satf's curls came to
# 0.79 of Cycles' luminance, 0.89 at the reference's width; 320x240, 16 spp.)
# The sparse strands keep a visible 0.3, as the tests that read them are
# rendered a few hundred pixels wide.
THICKNESS = {"fur": None, "sparse": 0.3, "straight": None, "curls": None}


def fibre_width(strands):
    """A hair fibre's width: 1e-3 of the strands' bounding-box diagonal."""
    lo = [min(p[c] for s in strands for p in s) for c in range(3)]
    hi = [max(p[c] for s in strands for p in s) for c in range(3)]
    return 1e-3 * math.sqrt(sum((h - l) ** 2 for l, h in zip(lo, hi)))


# ---- the file --------------------------------------------------------------

def hair_bytes(strands, thickness, per_point, taper, info):
    n_points = sum(len(s) for s in strands)
    flags = 1 | 2 | (4 if per_point else 0)
    header = struct.pack("<4sIIIIff3f", b"HAIR", len(strands), n_points, flags,
                         0, thickness, 0.0, 0.35, 0.22, 0.12)
    header += info.encode("ascii")[:87].ljust(88, b"\0")
    assert len(header) == 128
    segs = array("H", (len(s) - 1 for s in strands))
    pts = array("f", (c for s in strands for p in s for c in p))
    parts = [header, segs, pts]
    if per_point:
        parts.append(array("f", (thickness * (1.0 - (1.0 - taper) * k /
                                              (len(s) - 1))
                                 for s in strands for k in range(len(s)))))
    if sys.byteorder != "little":
        for a in parts[1:]:
            a.byteswap()
    return b"".join(p if isinstance(p, bytes) else p.tobytes() for p in parts)


def write_atomic(path, data):
    if os.path.dirname(path):
        os.makedirs(os.path.dirname(path), exist_ok=True)
    tmp = "%s.tmp-%d" % (path, os.getpid())
    with open(tmp, "wb") as f:
        f.write(data)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def positive(kind):
    def parse(text):
        try:
            v = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError("expected a number, got %r" % text)
        if not v > 0 or (kind is float and not math.isfinite(v)):
            raise argparse.ArgumentTypeError("%s is not positive" % text)
        return v
    return parse


def main(argv):
    ap = argparse.ArgumentParser(
        prog="gen-strands.py", add_help=False, usage=__doc__.split("\n\n")[1],
        description=None)
    ap.add_argument("kind", nargs="?")
    ap.add_argument("-o", "--output")
    ap.add_argument("--strands", type=positive(int))
    ap.add_argument("--points", type=positive(int))
    ap.add_argument("--radius", type=positive(float), default=31.0)
    ap.add_argument("--length", type=positive(float))
    ap.add_argument("--thickness", type=positive(float))
    ap.add_argument("--per-point-thickness", action="store_true")
    ap.add_argument("--taper", type=positive(float), default=0.3)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("-q", "--quiet", action="store_true")
    ap.add_argument("-h", "--help", action="store_true")
    a = ap.parse_args(argv)
    if a.help:
        print(__doc__.strip())
        return 0
    if a.kind not in KINDS:
        ap.error("KIND must be one of %s (got %r)" % (", ".join(KINDS), a.kind))
    if not a.output:
        ap.error("-o OUT.hair is required")
    if not a.output.lower().endswith(".hair"):
        ap.error("-o %s: writes a cyHair file; give it a name ending in .hair"
                 % a.output)
    if a.points is not None and not 2 <= a.points <= 65536:
        ap.error("--points %d: a strand needs 2..65536 points" % a.points)
    if a.taper > 1.0:
        ap.error("--taper %g: the tip is at most as thick as the root" % a.taper)
    n, pts = DEFAULTS[a.kind]
    n = a.strands or n
    pts = a.points or pts
    length = a.length or LENGTHS[a.kind] * a.radius
    rng = random.Random(a.seed)
    strands = KINDS[a.kind](rng, n, pts, a.radius, length)
    info = "satf gen-strands.py %s seed %d R %g" % (a.kind, a.seed, a.radius)
    thickness = a.thickness or THICKNESS[a.kind] or fibre_width(strands)
    data = hair_bytes(strands, thickness, a.per_point_thickness, a.taper,
                      info)
    write_atomic(a.output, data)
    if not a.quiet:
        lo = [min(p[c] for s in strands for p in s) for c in range(3)]
        hi = [max(p[c] for s in strands for p in s) for c in range(3)]
        total = sum(len(s) for s in strands)
        print("%s: %s, %d strands, %d points, bounds (%.1f %.1f %.1f) - "
              "(%.1f %.1f %.1f), %d bytes"
              % (a.output, a.kind, len(strands), total, *lo, *hi, len(data)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
