"""The satf hair add-on, headless: a generated groom (a sphere with 60 hair
particles, a material, a camera and a sun) exported through File > Export >
satf hair; the .hair file is read back and held to Blender's own numbers
(every strand's root and tip, its thickness and colour, turned Y-up), and
the scene's camera projects the roots where Blender's camera does
(world_to_camera_view); the groom converted to a Curves object with a
radius and a colour per point exports every point, radius and colour as
Blender holds them. Exits non-zero on the first mismatch.

usage: blender -b --factory-startup --python-exit-code 1 --python
       test_addon.py -- ADDON_PARENT OUT_DIR"""
import json
import math
import os
import struct
import sys

import bpy
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

addon_parent, out_dir = sys.argv[sys.argv.index("--") + 1:][:2]
sys.path.insert(0, addon_parent)
import satf_hair  # noqa: E402

satf_hair.register()


def check(cond, what):
    if not cond:
        raise SystemExit("test_addon: " + what)


def close(a, b, tol):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


# ---- the groom ----------------------------------------------------------------
for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)
scene = bpy.context.scene
scene.render.resolution_x, scene.render.resolution_y = 320, 240
scene.render.resolution_percentage = 100
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.1, location=(0.2, 0.3, 1.5),
                                     segments=16, ring_count=8)
head = bpy.context.active_object
head.modifiers.new("hair", "PARTICLE_SYSTEM")
settings = head.particle_systems[0].settings
settings.type = "HAIR"
settings.count = 60
settings.hair_length = 0.15
settings.display_step = 3
settings.child_type = "NONE"
settings.root_radius, settings.tip_radius, settings.radius_scale = 1.0, 0.5, 0.002
mat = bpy.data.materials.new("hair")
mat.diffuse_color = (0.5, 0.25, 0.125, 1.0)
head.data.materials.append(mat)

cam_data = bpy.data.cameras.new("cam")
cam = bpy.data.objects.new("cam", cam_data)
scene.collection.objects.link(cam)
cam.location = (0.5, -0.9, 1.7)
cam.rotation_euler = (Vector((0.2, 0.3, 1.55)) - cam.location).to_track_quat(
    "-Z", "Y").to_euler()
scene.camera = cam
sun_data = bpy.data.lights.new("sun", "SUN")
sun_data.energy = 3.0
sun = bpy.data.objects.new("sun", sun_data)
scene.collection.objects.link(sun)
sun.rotation_euler = (0.6, 0.2, 0.4)
bpy.context.view_layer.update()
for obj in bpy.data.objects:
    obj.select_set(obj == head)
bpy.context.view_layer.objects.active = head

# ---- the export, as the menu runs it -------------------------------------------
hair_path = os.path.join(out_dir, "groom.hair")
rc = bpy.ops.export_scene.satf_hair(filepath=hair_path)
check(rc == {"FINISHED"}, "the export operator returned %s" % rc)



def read_hair(path):
    """A .hair file with segments, points, thickness and colour: (segments,
    points, thickness, colours), flat tuples as the file holds them."""
    with open(path, "rb") as f:
        data = f.read()
    check(data[:4] == b"HAIR", "%s: no HAIR signature" % path)
    n, n_points, flags = struct.unpack_from("<III", data, 4)
    check(flags == 1 | 2 | 4 | 16, "%s: flags %d: not segments, points, "
          "thickness and colour" % (path, flags))
    segs = struct.unpack_from("<%dH" % n, data, 128)
    check(sum(s + 1 for s in segs) == n_points, "segments do not add up")
    at = 128 + 2 * n
    pts = struct.unpack_from("<%df" % (3 * n_points), data, at)
    at += 12 * n_points
    thick = struct.unpack_from("<%df" % n_points, data, at)
    at += 4 * n_points
    cols = struct.unpack_from("<%df" % (3 * n_points), data, at)
    check(at + 12 * n_points == len(data), "%s: the file's length is not its "
          "arrays'" % path)
    return segs, pts, thick, cols


segs, pts, thick, cols = read_hair(hair_path)
n = len(segs)
check(n == 60, "%d strands, Blender has 60" % n)
check(all(s == 8 for s in segs), "strands are not 9 points (display step 3)")

# Blender's numbers: the hair keys in object space (HairKey.co_object; the
# evaluated keys' .co cannot be read in 3.4)
evaluated = head.evaluated_get(bpy.context.evaluated_depsgraph_get())
psys = evaluated.particle_systems[0]
modifier = evaluated.modifiers["hair"]
check(len(psys.particles) == 60, "Blender's particle system holds %d "
      "particles, not 60" % len(psys.particles))
m = head.matrix_world
first = 0
for i, p in enumerate(psys.particles):
    root = satf_hair.to_satf(m @ p.hair_keys[0].co_object(evaluated, modifier,
                                                          p))
    tip = satf_hair.to_satf(m @ p.hair_keys[-1].co_object(evaluated, modifier,
                                                          p))
    last = first + segs[i]
    check(close(pts[3 * first:3 * first + 3], root, 1e-5),
          "strand %d root %s, Blender's %s" % (i, pts[3 * first:3 * first + 3],
                                                root))
    check(close(pts[3 * last:3 * last + 3], tip, 1e-5),
          "strand %d tip %s, Blender's %s" % (i, pts[3 * last:3 * last + 3],
                                               tip))
    check(abs(thick[first] - 0.002) < 1e-7 and abs(thick[last] - 0.001) < 1e-7,
          "strand %d thickness %g..%g, Blender's 0.002..0.001"
          % (i, thick[first], thick[last]))
    check(close(cols[3 * first:3 * first + 3], (0.5, 0.25, 0.125), 1e-6),
          "strand %d colour %s" % (i, cols[3 * first:3 * first + 3]))
    first = last + 1
# upright: Blender's up (z) is satf's y; the hair grows out of the sphere
ys = pts[1::3]
check(min(ys) > 1.5 - 0.1 - 1e-4 - 0.15 and max(ys) < 1.5 + 0.1 + 0.15 + 1e-4,
      "the hair's height is not Blender's z")

# ---- the scene: the camera projects the roots where Blender's does ----------
with open(os.path.join(out_dir, "groom.json")) as f:
    sc = json.load(f)
check(os.path.exists(os.path.join(out_dir, "groom.head.obj")), "no head OBJ")
check(sc["image"] == {"width": 320, "height": 240}, "image %s" % sc["image"])
check(sc["lights"][0]["type"] == "directional" and
      abs(sc["lights"][0]["intensity"] - 3.0) < 1e-6, "the sun is not there")
check(len(sc.get("meshes", [])) == 1, "the head is not the scene's mesh")
c = sc["camera"]
eye, target, up = Vector(c["position"]), Vector(c["target"]), Vector(c["up"])
check(close(eye, satf_hair.to_satf(cam.matrix_world.translation), 1e-5),
      "camera position %s" % list(eye))
fwd = (target - eye).normalized()
right = fwd.cross(up).normalized()
upv = right.cross(fwd)
t = math.tan(math.radians(c["fov_y"]) / 2)
worst = 0.0
for p in psys.particles:
    w = m @ p.hair_keys[-1].co_object(evaluated, modifier, p)
    want = world_to_camera_view(scene, cam, w)
    d = Vector(satf_hair.to_satf(w)) - eye
    z = d.dot(fwd)
    x = d.dot(right) / (z * t * 320 / 240)
    y = d.dot(upv) / (z * t)
    got = (0.5 + 0.5 * x, 0.5 + 0.5 * y)
    worst = max(worst, abs(got[0] - want.x) * 320, abs(got[1] - want.y) * 240)
check(worst < 0.01, "the satf camera puts a tip %.3g pixels from Blender's"
      % worst)
print("test_addon: 60 strands and the camera match Blender's (worst %.2g px)"
      % worst)

# ---- a Curves object (Blender 3.3+), made from the groom headless ----------
# Blender's own conversion of the particle hair, moved off the origin (its
# transform must apply), given a radius per point and a colour per point
# (3.4 has no Curves.add_curves); exported alone and held to its numbers:
# positions turned Y-up, thickness twice the radius, the colours as given.
for obj in bpy.data.objects:
    obj.select_set(obj == head)
bpy.context.view_layer.objects.active = head
rc = bpy.ops.curves.convert_from_particle_system()
check(rc == {"FINISHED"}, "Blender's conversion to Curves returned %s" % rc)
curves = bpy.context.view_layer.objects.active
check(curves is not None and curves.type == "CURVES",
      "the conversion made no Curves object")
curves.location = (0.05, -0.1, 0.2)
bpy.context.view_layer.update()
cd = curves.data
n_pts = len(cd.points)
radius = cd.attributes.get("radius") or cd.attributes.new("radius", "FLOAT",
                                                           "POINT")
for k, d in enumerate(radius.data):
    d.value = 0.001 + 0.0001 * (k % 9)
tint = cd.color_attributes.new("tint", "FLOAT_COLOR", "POINT")
for k, d in enumerate(tint.data):
    d.color = (0.1 + 0.8 * (k % 9) / 8, 0.3, 0.6 - 0.5 * (k % 9) / 8, 1.0)
for obj in bpy.data.objects:
    obj.select_set(obj == curves)
bpy.context.view_layer.objects.active = curves
curves_path = os.path.join(out_dir, "curves.hair")
rc = bpy.ops.export_scene.satf_hair(filepath=curves_path, make_scene=False)
check(rc == {"FINISHED"}, "the Curves export returned %s" % rc)
segs, pts, thick, cols = read_hair(curves_path)
n, n_points = len(segs), len(thick)
check(n == len(cd.curves) == 60, "%d strands, Blender's Curves has %d"
      % (n, len(cd.curves)))
check(n_points == n_pts, "%d points, Blender's Curves has %d" % (n_points,
                                                                n_pts))
m = curves.matrix_world
k = 0
for i, c in enumerate(cd.curves):
    check(segs[i] + 1 == c.points_length, "curve %d: %d points, Blender's %d"
          % (i, segs[i] + 1, c.points_length))
    for j in range(c.points_length):
        q = c.first_point_index + j
        w = m @ cd.points[q].position
        want = (w.x, w.z, -w.y)  # Z-up to Y-up
        check(close(pts[3 * k:3 * k + 3], want, 1e-5),
              "curve %d point %d at %s, Blender's %s"
              % (i, j, pts[3 * k:3 * k + 3], want))
        check(abs(thick[k] - 2.0 * radius.data[q].value) < 1e-7,
              "curve %d point %d thickness %g, Blender's radius %g"
              % (i, j, thick[k], radius.data[q].value))
        check(close(cols[3 * k:3 * k + 3], tint.data[q].color[:3], 1e-6),
              "curve %d point %d colour %s, Blender's %s"
              % (i, j, cols[3 * k:3 * k + 3], tuple(tint.data[q].color[:3])))
        k += 1
print("test_addon: a Curves object's %d curves, %d points, radii and colours "
      "match Blender's" % (n, n_points))
