#!/usr/bin/env python3
"""Generates samples/hair_7b.json, hair_7c.json and hair_7d.json: SATF Table
1 columns 7(b)-7(d) (Fig. 7, human hair), three hairstyles on the head of
scripts/gen-head.py (scalp: a sphere of radius 10 at the origin, face +z):

  7(b) long straight hair, 12 clusters x 5 layers, 34 x 30 HSVs per layer
       (61 200 HSVs), 19 900 strands (table: 12, 60, 61K, 20K);
  7(c) four thick wavy locks, 4 clusters x 15 layers, 53 x 40 HSVs per layer
       (127 200 HSVs), 20 000 strands (table: 4, 60, 127K, 20K);
  7(d) a short bob, 6 clusters x 10 layers, 42 x 25 HSVs per layer
       (63 000 HSVs), 9 000 strands (table: 6, 60, 63K, 9K).

Every prototype is drawn in the x = 0 plane on the +z (face) side, its
root on the scalp, and its instances are rotations about the vertical axis
through the head's centre (turning a prototype by `angle` moves it to that
azimuth), so every root stays on the scalp. Deterministic: running it again
writes the same bytes. usage: gen-table1-samples.py [SAMPLES_DIR]
"""
import json
import math
import os
import sys

ROOT_R = 10.8  # roots just outside the radius-10 scalp (half a minor axis)


def scalp(polar_deg, r=ROOT_R):
    """A control point at polar angle (from +y) on the face side."""
    p = math.radians(polar_deg)
    return [0.0, r * math.cos(p), r * math.sin(p)]


def hang(y, rho, x=0.0):
    """A control point of hair hanging at height y, rho from the axis."""
    return [x, y, rho]


def at_az(y, rho, az_deg, lateral=0.0):
    """A control point at height y, rho from the axis, at azimuth az (from
    +z towards +x), moved sideways (around the head) by lateral."""
    a = math.radians(az_deg)
    return [rho * math.sin(a) + lateral * math.cos(a), y,
            rho * math.cos(a) - lateral * math.sin(a)]


def sweep(az_deg, tail):
    """A front lock on the +x side: its root at a centre parting above the
    forehead, over the scalp sideways to azimuth az, then the tail (points
    at that azimuth). Leaving the root almost along +x makes z the least
    aligned axis with the first tangent, so the rotation-minimising frame
    puts the half-axis a front to back: the lock lies flat on the scalp."""
    def sph(r, polar, az):
        p, a = math.radians(polar), math.radians(az)
        return [r * math.sin(p) * math.sin(a), r * math.cos(p),
                r * math.sin(p) * math.cos(a)]
    return [sph(ROOT_R, 16, 4), sph(11.2, 45, 60),
            sph(11.6, 78, az_deg)] + tail


def mirror(points):
    """The same lock on the -x side (the hairstyles are symmetric; a
    mirrored copy, since an instance's rotation cannot mirror)."""
    return [[-p[0], p[1], p[2]] for p in points]


def rounded(points):
    return [[round(c, 3) for c in p] for p in points]


def flip(points):
    """The same profile on the back of the head (-z)."""
    return [[p[0], p[1], -p[2]] for p in points]


def macro(name, traj, a, b, shell, strands, seed, layout, angles, twist=0):
    density = {"type": "procedural", "strands": strands, "seed": seed}
    density.update(layout)
    density["strand_width"] = 0.05
    return {
        "name": name,
        "prototype": {"trajectory": rounded(traj), "a": a, "b": b,
                      "twist": twist, "shell": shell, "density": density},
        "instances": [{"rotate": {"axis": [0, 1, 0], "angle": g}}
                      if g else {} for g in angles] if angles else [{}],
    }


def scene(description, camera, macros):
    return {
        "description": description,
        "database": "../out/satf-default.hrirdb.exr",
        "meshes": [{"file": "../out/head.obj", "color": [0.55, 0.42, 0.36]}],
        "image": {"width": 640, "height": 480},
        "camera": camera,
        "lights": [
            {"type": "directional", "direction": [-0.5, -0.55, -0.67],
             "color": [1.0, 0.97, 0.92], "intensity": 1.0},
            {"type": "directional", "direction": [0.8, -0.1, -0.6],
             "color": [0.75, 0.82, 1.0], "intensity": 0.3}],
        "background": [0.16, 0.17, 0.2],
        "material": {"f_dif": [0.24, 0.15, 0.09], "k_dif": 0.7,
                     "k_speI": 0.3, "k_speII": 0.4, "exponent_I": 80,
                     "exponent_II": 24, "shift": 0.1, "k_shadow": 0.6,
                     "noise": 0.5},
        "effects": {"satf": True, "secondary_highlight": True,
                    "self_shadow": True, "cluster_shadows": True},
        "macro_clusters": macros,
    }


def long_straight():
    """7(b): 6 back clusters, 4 side clusters and 2 front locks falling
    straight past the shoulders from a centre parting."""
    shell = {"layers": 5, "st": 34, "su": 30, "core": 0.5}
    back = flip([scalp(14, 10.8), scalp(45, 11.2), scalp(80, 11.5), hang(-6, 11.9),
                 hang(-14, 12.0), hang(-24, 11.8)])
    side = [scalp(22, 10.8), scalp(55, 11.2), scalp(85, 11.6), hang(-6, 11.9),
            hang(-14, 12.0), hang(-23, 11.8)]
    front = sweep(62, [at_az(0, 12.0, 62), at_az(-10, 12.4, 62),
                       at_az(-20, 12.2, 62)])
    macros = [
        macro("back", back, [1.6, 2.8, 3.0, 3.0, 2.9, 2.4],
              [0.7, 0.9, 0.9, 0.9, 0.8, 0.6], shell, 1700, 91,
              {"layout": "uniform"}, [-75, -45, -15, 15, 45, 75]),
        macro("sides", side, [1.6, 2.6, 2.8, 2.8, 2.6, 2.1],
              [0.7, 0.9, 0.9, 0.9, 0.8, 0.6], shell, 1600, 92,
              {"layout": "gradient", "gradient": 0.5}, [-108, -80, 80, 108]),
    ]
    for k, (side_name, traj) in enumerate((("right", front),
                                           ("left", mirror(front)))):
        macros.append(macro(
            "front " + side_name, traj, [2.4, 3.2, 3.0, 2.6, 2.4, 2.0],
            [0.7, 0.8, 0.8, 0.8, 0.7, 0.5], shell, 1650, 93 + 10 * k,
            {"layout": "clumped", "clumps": 6, "clump_spread": 0.2}, None))
    camera = {"position": [30.0, 4.0, 50.0], "target": [0.0, -6.0, 0.0],
              "up": [0, 1, 0], "fov_y": 40.0}
    return scene(
        "SATF Table 1 column 7(b): long straight hair of 12 clusters "
        "(4 macro-clusters: 6 back, 4 side, and a front lock each side of "
        "a centre parting) on a head-sized scalp, a sphere of radius 10 at the origin "
        "facing +z (60 layers, ~61K HSVs, ~20K strands).", camera, macros)


def wave(y0, y1, rho, n, amp, period, phase, az=0.0):
    """Control points of a lock hanging from y0 to y1 at azimuth az that
    swings sideways (around the head) as a sine of the height: its waves."""
    pts = []
    for i in range(n):
        y = y0 + (y1 - y0) * i / (n - 1)
        w = min(1.0, i / 2.0)  # the wave grows in below the scalp
        pts.append(at_az(y, rho, az, w * amp *
                         math.sin(2 * math.pi * (y0 - y) / period + phase)))
    return pts


def taper(n, head, first, last):
    """n control values: the given ones over the scalp, then a straight
    ramp from first to last down the hanging part."""
    k = n - len(head)
    return head + [round(first + (last - first) * i / (k - 1), 3)
                   for i in range(k)]


def wavy_locks():
    """7(c): four thick wavy locks, two down the back, two framing the face,
    each a wide, dense cluster that narrows and twists to its tip."""
    shell = {"layers": 15, "st": 53, "su": 40, "core": 0.5}
    back = flip([scalp(12, 11.4), scalp(50, 11.8), scalp(85, 12.6)] +
                wave(-3, -22, 13.0, 14, 1.8, 8.0, 0.0))
    front = sweep(74, wave(-3, -20, 13.2, 12, 1.5, 7.0, 1.0, 74))
    macros = [
        macro("back locks", back, taper(17, [3.0, 5.2, 5.6], 4.8, 1.6),
              taper(17, [1.3, 1.9, 2.0], 2.0, 0.8), shell, 5000, 94,
              {"layout": "clumped", "clumps": 9, "clump_spread": 0.22},
              [-52, 52], twist=taper(17, [0, 0, 0], 0.2, 2.4)),
    ]
    for k, (side_name, traj) in enumerate((("right", front),
                                           ("left", mirror(front)))):
        macros.append(macro(
            "face lock " + side_name, traj,
            taper(15, [3.2, 4.6, 5.0], 4.2, 1.5),
            taper(15, [1.2, 1.8, 1.9], 1.9, 0.7), shell, 5000, 95 + 10 * k,
            {"layout": "gradient", "gradient": 0.6}, None,
            twist=taper(15, [0, 0, 0], -0.2, -2.1)))
    camera = {"position": [32.0, 4.0, 50.0], "target": [0.0, -5.0, 0.0],
              "up": [0, 1, 0], "fov_y": 40.0}
    return scene(
        "SATF Table 1 column 7(c): four thick wavy locks (3 macro-clusters: "
        "2 down the back, and one framing the face each side of a centre "
        "parting) on a head-sized scalp, a sphere "
        "of radius 10 at the origin facing +z (60 layers, ~127K HSVs, ~20K "
        "strands).", camera, macros)


def bob():
    """7(d): a chin-length bob: 4 clusters over the crown and the back, 2
    over the temples, all curling in under the jaw line."""
    shell = {"layers": 10, "st": 42, "su": 25, "core": 0.5}
    back = flip([scalp(10), scalp(40, 11.2), scalp(75, 11.8), hang(-2, 12.2),
                 hang(-7, 12.0), hang(-9, 10.6)])
    side = sweep(64, [at_az(-3, 12.2, 64), at_az(-7.5, 11.6, 64),
                      at_az(-9, 10.2, 64)])
    macros = [
        macro("crown and back", back, [1.8, 3.4, 3.8, 3.8, 3.6, 3.0],
              [0.7, 1.0, 1.1, 1.1, 1.0, 0.7], shell, 1500, 96,
              {"layout": "uniform"}, [-67, -22, 22, 67]),
    ]
    for k, (side_name, traj) in enumerate((("right", side),
                                           ("left", mirror(side)))):
        macros.append(macro(
            "temple " + side_name, traj, [3.0, 3.6, 3.6, 3.6, 3.3, 2.8],
            [0.7, 1.0, 1.1, 1.1, 1.0, 0.7], shell, 1500, 97 + 10 * k,
            {"layout": "holes", "holes": 3, "hole_radius": 0.15}, None))
    camera = {"position": [26.0, 9.0, 42.0], "target": [0.0, -1.0, 0.0],
              "up": [0, 1, 0], "fov_y": 38.0}
    return scene(
        "SATF Table 1 column 7(d): a chin-length bob of 6 clusters "
        "(3 macro-clusters: 4 over the crown and back, and one over each "
        "temple from a centre parting) "
        "on a head-sized scalp, a sphere of radius 10 at the origin facing "
        "+z (60 layers, 63K HSVs, 9K strands).", camera, macros)


def to_json(v, indent=0):
    """JSON with objects one key a line and arrays of numbers (or of number
    triples) on one line, like the hand-written samples."""
    pad = "  " * indent
    if isinstance(v, dict):
        if all(not isinstance(x, (dict, list)) or
               (isinstance(x, list) and len(x) <= 4) for x in v.values()) \
                and len(json.dumps(v)) < 72:
            return json.dumps(v, separators=(", ", ": "))
        items = ['%s  %s: %s' % (pad, json.dumps(k), to_json(x, indent + 1))
                 for k, x in v.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(v, list) and v and isinstance(v[0], dict):
        items = [pad + "  " + to_json(x, indent + 1) for x in v]
        return "[\n" + ",\n".join(items) + "\n" + pad + "]"
    return json.dumps(v, separators=(", ", ": "))


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "samples")
    for name, build in (("hair_7b", long_straight), ("hair_7c", wavy_locks),
                        ("hair_7d", bob)):
        data = build()
        n = sum(len(m["instances"]) for m in data["macro_clusters"])
        layers = hsv = strands = 0
        for m in data["macro_clusters"]:
            k, sh = len(m["instances"]), m["prototype"]["shell"]
            layers += k * sh["layers"]
            hsv += k * sh["layers"] * sh["st"] * sh["su"]
            strands += k * m["prototype"]["density"]["strands"]
        path = os.path.join(out_dir, name + ".json")
        with open(path, "w") as f:
            text = to_json(data) + "\n"
            assert json.loads(text) == data
            f.write(text)
        print("%s: %d clusters, %d layers, %d HSVs, %d strands" %
              (path, n, layers, hsv, strands))


if __name__ == "__main__":
    main()
