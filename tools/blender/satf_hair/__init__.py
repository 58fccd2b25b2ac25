"""satf hair: Blender hair into the satf hair renderer.

File > Export > satf hair writes the selected objects' hair (particle hair
systems and Curves objects) as a cyHair .hair file with per-point thickness
(a Curves object's radius attribute, doubled) and colour (a Curves object's
colour attribute on its points or curves, else the material's), the emitter mesh as the head (OBJ), and, through satf-import, a
satf scene with Blender's active camera, its sun and point lights and the
render resolution. Blender is Z-up and satf Y-up: every position turns by
(x, y, z) -> (x, z, -y). The satf panel (Properties > Render > satf) exports
the selection and opens it in satf-view, or renders an EXR with satf-render.
"""

bl_info = {
    "name": "satf hair",
    "author": "satf",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "File > Export > satf hair; Properties > Render > satf",
    "description": "Export hair to the satf renderer and view or render it",
    "category": "Import-Export",
}

import json
import math
import os
import shutil
import struct
import subprocess

import bpy
from bpy.props import BoolProperty, StringProperty
from bpy_extras.io_utils import ExportHelper
from mathutils import Vector


def to_satf(v):
    """Blender's Z-up to satf's Y-up."""
    return (v[0], v[2], -v[1])


# ---- strands ---------------------------------------------------------------

def material_colour(obj):
    """The hair's colour: the Principled Hair BSDF's Color (colour mode) of
    the object's active material, else its viewport colour; None without a
    material."""
    mat = obj.active_material
    if mat is None:
        return None
    if mat.use_nodes and mat.node_tree:
        for node in mat.node_tree.nodes:
            if node.type == "BSDF_HAIR_PRINCIPLED" and "Color" in node.inputs:
                return tuple(node.inputs["Color"].default_value[:3])
    return tuple(mat.diffuse_color[:3])


def particle_strands(obj, eval_obj, depsgraph):
    """(points, thickness, None) per strand of every hair particle system,
    world space, as Blender displays them (parents and children)."""
    strands = []
    for psys in eval_obj.particle_systems:
        s = psys.settings
        if s.type != "HAIR":
            continue
        steps = (1 << s.display_step) + 1
        count = len(psys.particles) + len(psys.child_particles)
        root = s.root_radius * s.radius_scale
        tip = s.tip_radius * s.radius_scale
        for p in range(count):
            pts = [tuple(psys.co_hair(object=eval_obj, particle_no=p, step=k))
                   for k in range(steps)]
            if any(c != c for q in pts for c in q):  # NaN: hidden child
                continue
            th = [root + (tip - root) * k / (steps - 1) for k in range(steps)]
            strands.append((pts, th, None))
    return strands


def colour_attribute(data):
    """A Curves object's colour attribute (the active one, else the first)
    on its points or curves: (domain, per-element linear RGB), or None."""
    group = data.color_attributes
    found = [getattr(group, "active_color", None)] + list(group)
    for attr in found:
        if attr is not None and attr.domain in ("POINT", "CURVE"):
            return attr.domain, [tuple(d.color[:3]) for d in attr.data]
    return None


def curves_strands(eval_obj):
    """(points, thickness, colours) per curve of a Curves object, world
    space; colours per point (None without a colour attribute)."""
    data = eval_obj.data
    m = eval_obj.matrix_world
    strands = []
    radius = None
    if "radius" in data.attributes:
        radius = [d.value for d in data.attributes["radius"].data]
    colour = colour_attribute(data)
    for i, c in enumerate(data.curves):
        first, n = c.first_point_index, c.points_length
        pts = [tuple(m @ data.points[first + k].position) for k in range(n)]
        th = [2.0 * (radius[first + k] if radius else 0.005) for k in range(n)]
        cols = None
        if colour and colour[0] == "POINT":
            cols = colour[1][first:first + n]
        elif colour:
            cols = [colour[1][i]] * n
        strands.append((pts, th, cols))
    return strands


def gather(context, objects):
    """Every strand of the objects (particle hair, Curves) as (points,
    thickness), the emitters (meshes with hair), and per strand its points'
    colours (the Curves' attribute, else the material's; None without
    either)."""
    depsgraph = context.evaluated_depsgraph_get()
    strands, colours, emitters = [], [], []
    for obj in objects:
        eval_obj = obj.evaluated_get(depsgraph)
        got = []
        if obj.type == "CURVES":
            got = curves_strands(eval_obj)
            surface = getattr(obj.data, "surface", None)
            if surface is not None and surface.type == "MESH":
                emitters.append(surface)
        elif obj.type == "MESH" and obj.particle_systems:
            got = particle_strands(obj, eval_obj, depsgraph)
            if got:
                emitters.append(obj)
        got = [g for g in got if len(g[0]) >= 2]
        strands += [(pts, th) for pts, th, _ in got]
        mat = material_colour(obj)
        colours += [cols if cols else [mat] * len(pts) if mat else None
                    for pts, _, cols in got]
    return strands, colours, emitters


def write_hair(path, strands, colours):
    """cyHair: "HAIR", counts, flags (segments, points, thickness, colour),
    defaults and 88 bytes of information, then the arrays; through a
    temporary file renamed into place."""
    if not strands:
        raise ValueError("no hair in the selection (select objects with hair "
                         "particle systems or Curves)")
    for pts, _ in strands:
        if len(pts) > 65536:
            raise ValueError("a strand of %d points: cyHair holds at most "
                             "65536" % len(pts))
    with_colour = all(c is not None for c in colours)
    n_points = sum(len(p) for p, _ in strands)
    flags = 1 | 2 | 4 | (16 if with_colour else 0)
    info = b"satf hair from Blender".ljust(88, b"\0")
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(b"HAIR")
        f.write(struct.pack("<III", len(strands), n_points, flags))
        f.write(struct.pack("<If", 0, 1.0))
        f.write(struct.pack("<f3f", 1.0, 0.5, 0.5, 0.5))
        f.write(info)
        f.write(struct.pack("<%dH" % len(strands),
                            *[len(p) - 1 for p, _ in strands]))
        for pts, _ in strands:
            for q in pts:
                f.write(struct.pack("<3f", *to_satf(q)))
        for _, th in strands:
            f.write(struct.pack("<%df" % len(th), *th))
        if with_colour:
            for cols in colours:
                for c in cols:
                    f.write(struct.pack("<3f", *c))
    os.replace(tmp, path)
    return len(strands), n_points


def write_head(path, context, emitters):
    """The emitters' evaluated meshes, world space, as one OBJ."""
    depsgraph = context.evaluated_depsgraph_get()
    tmp = path + ".tmp"
    base = 1
    with open(tmp, "w") as f:
        f.write("# satf head from Blender\n")
        for obj in emitters:
            eval_obj = obj.evaluated_get(depsgraph)
            mesh = eval_obj.to_mesh()
            m = eval_obj.matrix_world
            for v in mesh.vertices:
                f.write("v %.7g %.7g %.7g\n" % to_satf(m @ v.co))
            for poly in mesh.polygons:
                f.write("f %s\n" % " ".join(str(base + i)
                                            for i in poly.vertices))
            base += len(mesh.vertices)
            eval_obj.to_mesh_clear()
    os.replace(tmp, path)


# ---- the scene's view --------------------------------------------------------

def camera_json(scene, focus):
    """The active camera: position, a target along its view at the hair's
    distance, up, and fov_y from the lens and the sensor fit."""
    cam = scene.camera
    if cam is None:
        return None
    m = cam.matrix_world
    pos = m.translation
    forward = -(m.to_3x3() @ Vector((0, 0, 1))).normalized()
    up = (m.to_3x3() @ Vector((0, 1, 0))).normalized()
    dist = max((focus - pos).dot(forward), 1e-3 * max(1.0, pos.length))
    w = scene.render.resolution_x * scene.render.pixel_aspect_x
    h = scene.render.resolution_y * scene.render.pixel_aspect_y
    fit = cam.data.sensor_fit
    if fit == "VERTICAL" or (fit == "AUTO" and h > w):
        fov_y = cam.data.angle_y if fit == "VERTICAL" else cam.data.angle
    else:
        angle = cam.data.angle_x if fit == "HORIZONTAL" else cam.data.angle
        fov_y = 2.0 * math.atan(math.tan(0.5 * angle) * h / w)
    return {"position": list(to_satf(pos)),
            "target": list(to_satf(pos + forward * dist)),
            "up": list(to_satf(up)),
            "fov_y": math.degrees(fov_y)}


def lights_json(scene):
    """Sun lights as directional (travelling along the sun's -Z, intensity
    its strength), point lights as point (intensity the power over 4 pi,
    the radiant intensity)."""
    out = []
    for obj in scene.objects:
        if obj.type != "LIGHT" or obj.hide_render:
            continue
        light = obj.data
        colour = list(light.color)
        if light.type == "SUN":
            d = -(obj.matrix_world.to_3x3() @ Vector((0, 0, 1))).normalized()
            out.append({"type": "directional", "direction": list(to_satf(d)),
                        "color": colour, "intensity": light.energy})
        elif light.type == "POINT":
            out.append({"type": "point",
                        "position": list(to_satf(obj.matrix_world.translation)),
                        "color": colour,
                        "intensity": light.energy / (4.0 * math.pi)})
    return out


def hair_centre(strands):
    lo = [min(q[c] for pts, _ in strands for q in pts) for c in range(3)]
    hi = [max(q[c] for pts, _ in strands for q in pts) for c in range(3)]
    return Vector([(a + b) / 2 for a, b in zip(lo, hi)])


# ---- satf's programs ----------------------------------------------------------

def tool(context, name):
    """satf's program `name`: in the add-on's bin folder when set, else on
    the PATH."""
    prefs = context.preferences.addons.get(__name__)
    folder = prefs.preferences.bin_dir if prefs else ""
    if folder:
        path = os.path.join(bpy.path.abspath(folder), name)
        if os.access(path, os.X_OK):
            return path
        raise RuntimeError("%s is not in %s (the satf hair add-on's "
                           "preferences)" % (name, folder))
    path = shutil.which(name)
    if not path:
        raise RuntimeError("%s is not on the PATH: install satf (cmake "
                           "--install) or set its bin folder in the add-on's "
                           "preferences" % name)
    return path


def export(context, hair_path, objects, run_import=True):
    """Writes HAIR_PATH, its head (.head.obj) and, with run_import, its scene
    (.json) through satf-import; returns a summary dict."""
    strands, colours, emitters = gather(context, objects)
    n, points = write_hair(hair_path, strands, colours)
    stem = os.path.splitext(hair_path)[0]
    result = {"hair": hair_path, "strands": n, "points": points}
    head = None
    if emitters:
        head = stem + ".head.obj"
        write_head(head, context, emitters)
        result["head"] = head
    if not run_import:
        return result
    scene_path = stem + ".json"
    cmd = [tool(context, "satf-import"), hair_path, "-o", scene_path, "-q"]
    if head:
        cmd += ["--mesh", head]
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        raise RuntimeError("satf-import failed: " + run.stderr.strip())
    with open(scene_path) as f:
        scene = json.load(f)
    scene_view = context.scene
    cam = camera_json(scene_view, hair_centre(strands))
    if cam:
        scene["camera"] = cam
    lights = lights_json(scene_view)
    if lights:
        scene["lights"] = lights
    pct = scene_view.render.resolution_percentage / 100.0
    scene["image"] = {
        "width": max(1, int(scene_view.render.resolution_x * pct)),
        "height": max(1, int(scene_view.render.resolution_y * pct))}
    tmp = scene_path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(scene, f, indent=1)
    os.replace(tmp, scene_path)
    result["scene"] = scene_path
    return result


class SATF_OT_export_hair(bpy.types.Operator, ExportHelper):
    """Export the selected hair as cyHair with a satf scene"""
    bl_idname = "export_scene.satf_hair"
    bl_label = "Export satf hair"
    filename_ext = ".hair"
    filter_glob: StringProperty(default="*.hair", options={"HIDDEN"})
    make_scene: BoolProperty(
        name="satf scene",
        description="Also make the satf scene (satf-import), with Blender's "
                    "camera and lights",
        default=True)

    def execute(self, context):
        objects = context.selected_objects or [context.active_object]
        try:
            r = export(context, self.filepath, [o for o in objects if o],
                       self.make_scene)
        except (RuntimeError, ValueError, OSError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, "satf: %d strands, %d points to %s"
                    % (r["strands"], r["points"], r.get("scene", r["hair"])))
        return {"FINISHED"}


def work_dir(context):
    folder = bpy.path.abspath(context.scene.satf_dir or "//satf")
    if folder.startswith("//") or not os.path.isabs(folder):
        folder = os.path.join(bpy.app.tempdir or "/tmp", "satf")
    os.makedirs(folder, exist_ok=True)
    return folder


class SATF_OT_view(bpy.types.Operator):
    """Export the selected hair and open it in satf-view"""
    bl_idname = "satf.view"
    bl_label = "View in satf"
    render_exr: BoolProperty(default=False, options={"HIDDEN"})

    def execute(self, context):
        folder = work_dir(context)
        objects = [o for o in context.selected_objects] or \
            [context.active_object]
        try:
            r = export(context, os.path.join(folder, "hair.hair"),
                       [o for o in objects if o])
            if self.render_exr:
                exr = os.path.join(folder, "hair.exr")
                run = subprocess.run(
                    [tool(context, "satf-render"), r["scene"], "-o", exr,
                     "--aov", "--png", os.path.join(folder, "hair.png"), "-q"],
                    capture_output=True, text=True)
                if run.returncode != 0:
                    raise RuntimeError("satf-render failed: " +
                                       run.stderr.strip())
                self.report({"INFO"}, "satf: rendered " + exr)
            else:
                subprocess.Popen([tool(context, "satf-view"), r["scene"]])
                self.report({"INFO"}, "satf: viewing " + r["scene"])
        except (RuntimeError, ValueError, OSError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        return {"FINISHED"}


class SATF_PT_panel(bpy.types.Panel):
    bl_label = "satf"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"

    def draw(self, context):
        col = self.layout.column()
        col.prop(context.scene, "satf_dir")
        col.operator(SATF_OT_view.bl_idname, text="View in satf-view")
        op = col.operator(SATF_OT_view.bl_idname, text="Render EXR")
        op.render_exr = True


class SATF_AP_preferences(bpy.types.AddonPreferences):
    bl_idname = __name__
    bin_dir: StringProperty(
        name="satf bin folder",
        description="Where satf-import, satf-view and satf-render are "
                    "(empty: the PATH)",
        subtype="DIR_PATH", default="")

    def draw(self, context):
        self.layout.prop(self, "bin_dir")


def menu_export(self, context):
    self.layout.operator(SATF_OT_export_hair.bl_idname,
                         text="satf hair (.hair)")


CLASSES = (SATF_OT_export_hair, SATF_OT_view, SATF_PT_panel,
           SATF_AP_preferences)


def register():
    for c in CLASSES:
        bpy.utils.register_class(c)
    bpy.types.Scene.satf_dir = StringProperty(
        name="Folder", description="Where the panel's exports go",
        subtype="DIR_PATH", default="//satf")
    bpy.types.TOPBAR_MT_file_export.append(menu_export)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(menu_export)
    del bpy.types.Scene.satf_dir
    for c in reversed(CLASSES):
        bpy.utils.unregister_class(c)
