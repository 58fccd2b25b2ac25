"""An EXR with AOVs in Blender's compositor: an Image node on it offers the
view layer `satf` (no unnamed layer, which Blender lists as none) with the
passes as sockets. Exits non-zero otherwise.

usage: blender -b --factory-startup --python-exit-code 1 --python
       check_exr.py -- FILE.exr"""
import sys

import bpy

path = sys.argv[sys.argv.index("--") + 1]
img = bpy.data.images.load(path)
scene = bpy.context.scene
scene.use_nodes = True
node = scene.node_tree.nodes.new("CompositorNodeImage")
node.image = img
outs = [s.name for s in node.outputs if s.enabled]
print("check_exr: type %s layer %r outputs %s" % (img.type, node.layer, outs))
if img.type != "MULTILAYER" or node.layer != "satf":
    raise SystemExit("check_exr: the view layer is %r, not 'satf'" % node.layer)
for want in ("Combined", "Alpha", "diffuse", "specI", "specII", "shadow"):
    if want not in outs:
        raise SystemExit("check_exr: no %s socket (has %s)" % (want, outs))
