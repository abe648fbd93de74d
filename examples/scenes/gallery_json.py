# examples/scenes/gallery_json.py — writes gallery.json and gallery_spot.json: make_gallery()
# (pbr/src/gallery.cpp) as scene files; and gallery_ibl.json, the same spheres lit by the
# built-in studio environment alone (no point lights), ACES tone mapped. Roughness is computed in float32 exactly as
# gallery.cpp does and written with the fewest digits that give back the same float, so
# the files render the library gallery bit for bit (tested by ctest -R cli_scenes).
# Run from this folder: python3 gallery_json.py
import json, struct, sys
f32 = lambda x: struct.unpack('f', struct.pack('f', x))[0]
def shortest(x):
    for n in range(1, 18):
        s = '%.*g' % (n, x)
        if f32(float(s)) == x: return float(s)
rows = ["gold", "copper", "aluminium", "titanium", "plastic_red"]
cols = 7
first, last = f32(0.05), f32(1.0)
span = f32(last - first)
def scene(spot):
    objs = []
    for r, preset in enumerate(rows):
        for c in range(cols):
            t = f32(f32(c) / f32(cols - 1))
            rough = min(max(f32(first + f32(span * t)), 0.0), 1.0)
            tr = {"translate": [c - 3, 2 - r, 0]}
            if spot: tr["rotate"] = [0, 143.2394487827058, 0]
            objs.append({"mesh": "spot" if spot else "sphere",
                         "material": {"preset": preset, "roughness": shortest(rough)},
                         "transform": tr})
    meshes = ({"spot": {"file": "../../assets/models/spot/spot_triangulated.obj", "fit": 0.8}} if spot else
              {"sphere": {"type": "uv_sphere", "radius": 0.4, "segments": 64, "rings": 32}})
    return {
        "camera": {"position": [0, 0, 9], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 45, "near": 0.1, "far": 100},
        "lights": [{"type": "point", "position": p, "color": [1, 1, 1], "intensity": 60} for p in ([-4, 4, 6], [4, 4, 6], [0, -4, 6])],
        "ambient": [0.03, 0.03, 0.03],
        "meshes": meshes,
        "objects": objs,
        "render": {"width": 1280, "height": 720, "tonemap": "reinhard", "gamma": 2.2, "exposure": 0,
                   "background": [0, 0, 0]},
    }
def dump(obj):
    # One object per line keeps the file readable.
    lines = ["{"]
    keys = list(obj)
    for i, k in enumerate(keys):
        comma = "," if i + 1 < len(keys) else ""
        v = obj[k]
        if k in ("objects", "lights"):
            lines.append('  "%s": [' % k)
            lines += ["    " + json.dumps(o) + ("," if j + 1 < len(v) else "") for j, o in enumerate(v)]
            lines.append("  ]" + comma)
        else:
            lines.append('  "%s": %s%s' % (k, json.dumps(v), comma))
    lines.append("}")
    return "\n".join(lines) + "\n"
def ibl():
    s = scene(False)
    del s["lights"], s["ambient"]
    s["environment"] = {"background": "environment"}
    s["render"] = {"width": 1280, "height": 720, "tonemap": "aces"}
    order = ["camera", "environment", "meshes", "objects", "render"]
    return {k: s[k] for k in order}
def shadows():
    # The spheres before a wall, lit by one directional light from the upper left that casts
    # shadows (docs/design.md, "Shadows"): each sphere's shadow falls on the wall below and
    # right of it; bench_scenes renders it with shadows on and off.
    s = scene(False)
    s["lights"] = [{"type": "directional", "direction": [1, -1, -1.2], "color": [1, 1, 1], "intensity": 4,
                    "shadows": True}]
    s["meshes"]["wall"] = {"type": "plane", "width": 9, "depth": 6}
    s["objects"].append({"mesh": "wall", "material": {"base_color": [0.8, 0.8, 0.8], "roughness": 0.8},
                         "transform": {"rotate": [90, 0, 0], "translate": [0, 0, -0.6]}})
    return s
open("gallery.json", "w").write(dump(scene(False)))
open("gallery_shadows.json", "w").write(dump(shadows()))
open("gallery_ibl.json", "w").write(dump(ibl()))
open("gallery_spot.json", "w").write(dump(scene(True)))
