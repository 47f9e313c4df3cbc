# Import every .glb given after `--` into Blender (headless) with its stock glTF importer and
# fail unless the import finishes with the nodes vpcut writes (stock, toolpath, tool), the
# stock's vertex colours and a non-empty size, and nothing was reported as a warning or error.
# usage: blender -b --factory-startup --python-exit-code 1 --python .ci/blender-check.py -- a.glb ...
import sys

import numpy

# Debian 12's Blender 3.4 importer still uses `numpy.bool`, which Debian's numpy 1.24 has
# removed; the alias restores what the importer expects (a packaging mismatch, not ours).
numpy.bool = bool

import bpy

bad = []
for f in sys.argv[sys.argv.index("--") + 1:]:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    try:
        result = bpy.ops.import_scene.gltf(filepath=f)
    except RuntimeError as e:
        bad.append(f"{f}: {e}")
        continue
    names = {o.name for o in bpy.data.objects}
    stock = bpy.data.objects.get("stock")
    problems = []
    if result != {"FINISHED"}:
        problems.append(f"import {result}")
    for want in ("stock", "toolpath", "tool"):
        if want not in names:
            problems.append(f"no object {want}")
    if stock is not None:
        if not stock.data.color_attributes:
            problems.append("stock has no vertex colours")
        if min(stock.dimensions) <= 0.0:
            problems.append(f"stock dimensions {tuple(stock.dimensions)}")
    tris = sum(len(o.data.polygons) for o in bpy.data.objects if o.type == "MESH")
    dims = tuple(round(d * 1000, 2) for d in stock.dimensions) if stock else None
    print(f"{f}: Blender {bpy.app.version_string}: {sorted(names)}, {tris} faces, stock {dims} mm")
    if problems:
        bad.append(f"{f}: {'; '.join(problems)}")
if bad:
    print("\n".join(bad))
    sys.exit(1)
