#!/usr/bin/env python3
# Generates samples/anim_8.json (SATF Table 1, last column / Fig. 8): 40
# clusters in 5 macro-clusters on a head-sized scalp, swaying over 48 frames.
import json, math
R = 10.8
def polar_root(polar_deg, toward):  # toward: 'back' (-z), 'front' (+z)
    p = math.radians(polar_deg)
    z = R*math.sin(p) * (-1 if toward == 'back' else 1)
    return [0.0, round(R*math.cos(p), 3), round(z, 3)]

protos = [
  dict(name="back_upper",
       traj=[[0.0,10.367,-3.368],[0.0,8.769,-7.896],[0.0,4.104,-11.276],[0.0,-1.67,-11.883],[0,-7.5,-12.3],[0,-13.5,-12.0]],
       a=[1.3,1.9,1.9,1.8,1.6,1.1], b=[0.7,0.9,0.9,0.9,0.8,0.6],
       side=[1,0,0], out=[0,0,-1], angles=[-77,-55,-33,-11,11,33,55,77],
       seed=81, layout=dict(layout="clumped", clumps=5, clump_spread=0.18), phase=0.0, amp=2.2),
  dict(name="back_lower",
       traj=[polar_root(72,'back'),[0,-0.5,-11.5],[0,-5.0,-12.3],[0,-10.0,-12.3],[0,-14.0,-11.8]],
       a=[1.2,1.7,1.7,1.5,1.1], b=[0.6,0.8,0.8,0.8,0.6],
       side=[1,0,0], out=[0,0,-1], angles=[-72,-56,-40,-24,-8,8,24,40,56,72],
       seed=82, layout=dict(layout="uniform"), phase=0.6, amp=2.0),
  dict(name="nape",
       traj=[polar_root(105,'back'),[0,-6.0,-11.0],[0,-10.0,-11.2],[0,-14.0,-10.8]],
       a=[1.1,1.5,1.4,1.0], b=[0.6,0.8,0.7,0.5],
       side=[1,0,0], out=[0,0,-1], angles=[-56,-40,-24,-8,8,24,40,56],
       seed=83, layout=dict(layout="gradient", gradient=0.5), phase=1.2, amp=1.6),
  dict(name="fringe",
       traj=[polar_root(38,'front'),[0,7.2,9.8],[0,5.0,11.5],[0,2.8,11.9]],
       a=[1.1,1.6,1.4,1.0], b=[0.6,0.8,0.7,0.5],
       side=[1,0,0], out=[0,0,1], angles=[-40,-24,-8,8,24,40],
       seed=84, layout=dict(layout="uniform"), phase=0.3, amp=0.9),
  dict(name="sides",
       traj=[[8.1,7.294,0.0],[11.033,4.458,0.0],[12.1,0.0,0.0],[12.2,-6,0],[12.0,-11.5,0]],
       a=[1.2,1.8,1.8,1.6,1.2], b=[0.6,0.8,0.8,0.8,0.6],
       side=[0,0,1], out=[1,0,0], angles=[-45,-15,15,45,135,165,195,225],
       seed=85, layout=dict(layout="holes", holes=3, hole_radius=0.15), phase=0.9, amp=2.0),
]
FRAMES = [1, 7, 13, 19, 25, 31, 37, 43, 48]

def sway(p, f):
    ph = 2*math.pi*(f-1)/48.0 + p["phase"]
    n = len(p["traj"])
    out = []
    for i, q in enumerate(p["traj"]):
        w = (i/(n-1))**1.5
        s = p["amp"]*w*math.sin(ph)
        lift = 0.4*p["amp"]*w*0.5*(1-math.cos(ph))
        out.append([round(q[k] + s*p["side"][k] + lift*p["out"][k], 3) for k in range(3)])
    return out

def fmt(v):
    return json.dumps(v, separators=(", ", ": "))

L = []
L.append('{')
L.append('  "description": "SATF Table 1 column 8 (Fig. 8): an animated hairstyle of 40 clusters (5 macro-clusters) on a head-sized scalp, a sphere of radius 10 at the origin facing +z (80 layers, ~42K HSVs, ~21K strands), the hair swaying over frames 1-48 at 24 fps while the camera turns slowly.",')
L.append('  "database": "../out/satf-default.hrirdb.exr",')
# the head of scripts/gen-head.py, written into out/ by scripts/main.sh
L.append('  "meshes": [{"file": "../out/head.obj", "color": [0.55, 0.42, 0.36]}],')
L.append('  "image": {"width": 640, "height": 480},')
L.append('  "animation": {"fps": 24, "frames": [1, 48]},')
L.append('  "camera": {')
L.append('    "position": [26.0, 9.0, 42.0],')
L.append('    "target": [0.0, -1.0, 0.0],')
L.append('    "up": [0, 1, 0],')
L.append('    "fov_y": 38.0,')
L.append('    "keys": [')
cam = []
for f, az, h in [(1, None, 9.0), (24, 20.0, 8.0), (48, 8.0, 7.0)]:
    if az is None:
        cam.append('      {"frame": 1, "position": [26.0, 9.0, 42.0]}')
    else:
        d = math.hypot(26, 42)
        cam.append('      {"frame": %d, "position": [%.3f, %.1f, %.3f]}' % (f, d*math.sin(math.radians(az)), h, d*math.cos(math.radians(az))))
L.append(',\n'.join(cam))
L.append('    ]')
L.append('  },')
L.append('''  "lights": [
    {"type": "directional", "direction": [-0.5, -0.55, -0.67], "color": [1.0, 0.97, 0.92], "intensity": 1.0},
    {"type": "directional", "direction": [0.8, -0.1, -0.6], "color": [0.75, 0.82, 1.0], "intensity": 0.3}
  ],
  "background": [0.16, 0.17, 0.2],
  "material": {"f_dif": [0.24, 0.15, 0.09], "k_dif": 0.7, "k_speI": 0.3, "k_speII": 0.4, "exponent_I": 80, "exponent_II": 24, "shift": 0.1, "k_shadow": 0.6, "noise": 0.5},
  "effects": {"satf": true, "secondary_highlight": true, "self_shadow": true, "cluster_shadows": true},''')
L.append('  "macro_clusters": [')
mcs = []
for p in protos:
    m = []
    m.append('    {')
    m.append('      "name": "%s",' % p["name"])
    m.append('      "prototype": {')
    m.append('        "trajectory": %s,' % fmt(p["traj"]))
    m.append('        "a": %s,' % fmt(p["a"]))
    m.append('        "b": %s,' % fmt(p["b"]))
    m.append('        "twist": 0,')
    m.append('        "shell": {"layers": 2, "st": 21, "su": 25, "core": 0.5},')
    dens = dict(type="procedural", strands=525, seed=p["seed"]); dens.update(p["layout"]); dens["strand_width"] = 0.05
    m.append('        "density": %s,' % fmt(dens))
    m.append('        "keys": [')
    m.append(',\n'.join('          {"frame": %d, "trajectory": %s}' % (f, fmt(sway(p, f))) for f in FRAMES))
    m.append('        ]')
    m.append('      },')
    m.append('      "instances": [')
    m.append(',\n'.join('        {"rotate": {"axis": [0, 1, 0], "angle": %d}}' % a for a in p["angles"]))
    m.append('      ]')
    m.append('    }')
    mcs.append('\n'.join(m))
L.append(',\n'.join(mcs))
L.append('  ]')
L.append('}')
text = '\n'.join(L) + '\n'
json.loads(text)
open('/work/main/samples/anim_8.json', 'w').write(text)

# checks: roots on the scalp, distinct; trajectories outside the head at all keys
def roty(q, deg):
    t = math.radians(deg); c, s = math.cos(t), math.sin(t)
    return [q[0]*c + q[2]*s, q[1], -q[0]*s + q[2]*c]
roots = []
for p in protos:
    for a in p["angles"]:
        roots.append(roty(p["traj"][0], a))
    for f in FRAMES:
        for q in sway(p, f):
            assert math.dist(q, [0,0,0]) > 10.5, (p["name"], f, q)
mind = min(math.dist(roots[i], roots[j]) for i in range(len(roots)) for j in range(i+1, len(roots)))
print(len(roots), "clusters, min root distance", round(mind, 2), "root radii", round(min(math.dist(r,[0,0,0]) for r in roots),2), round(max(math.dist(r,[0,0,0]) for r in roots),2))
print(len(text), "bytes")
