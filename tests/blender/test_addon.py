"""The satf hair add-on, headless: a generated groom (a sphere with 60 hair
particles, a material, a camera and a sun) exported through File > Export >
satf hair; the .hair file is read back and held to Blender's own numbers
(every strand's root and tip, its thickness and colour, turned Y-up), and
the scene's camera projects the roots where Blender's camera does
(world_to_camera_view). Exits non-zero on the first mismatch.

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

with open(hair_path, "rb") as f:
    data = f.read()
check(data[:4] == b"HAIR", "no HAIR signature")
n, n_points, flags = struct.unpack_from("<III", data, 4)
check(flags == 1 | 2 | 4 | 16, "flags %d: not segments, points, thickness "
      "and colour" % flags)
check(n == 60, "%d strands, Blender has 60" % n)
segs = struct.unpack_from("<%dH" % n, data, 128)
check(sum(s + 1 for s in segs) == n_points, "segments do not add up")
check(all(s == 8 for s in segs), "strands are not 9 points (display step 3)")
at = 128 + 2 * n
pts = struct.unpack_from("<%df" % (3 * n_points), data, at)
at += 12 * n_points
thick = struct.unpack_from("<%df" % n_points, data, at)
at += 4 * n_points
cols = struct.unpack_from("<%df" % (3 * n_points), data, at)
check(at + 12 * n_points == len(data), "the file's length is not its arrays'")

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
