#!/usr/bin/env python3
"""hair_width.py FILE.hair EXPECTED: checks a cyHair file's header default
thickness against EXPECTED, a number or 'fibre' (1e-3 of the points'
bounding-box diagonal, the width scripts/gen-strands.py writes by default),
within float rounding; prints both and exits 1 when they differ."""
import struct
import sys


def main(path, expected):
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 128 or data[:4] != b"HAIR":
        print("%s: not a cyHair file" % path)
        return 1
    hairs, points, flags = struct.unpack_from("<III", data, 4)
    thickness = struct.unpack_from("<f", data, 20)[0]
    at = 128 + (2 * hairs if flags & 1 else 0)
    xyz = struct.unpack_from("<%df" % (3 * points), data, at)
    span = [max(xyz[c::3]) - min(xyz[c::3]) for c in range(3)]
    diag = sum(s * s for s in span) ** 0.5
    want = 1e-3 * diag if expected == "fibre" else float(expected)
    print("%s: thickness %.6g, expected %.6g (diagonal %.6g)"
          % (path, thickness, want, diag))
    return 0 if abs(thickness - want) <= 1e-5 * max(want, 1e-30) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
