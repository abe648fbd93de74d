#!/usr/bin/env python3
"""Small glTF files for cli/tests/driver.sh (info and batch groups), written into the
current folder from an image given on the command line:

  make_gltf.py IMAGE.png   ->  two.gltf (+ two.bin, tex.png), two.glb (the same, image
                               embedded in a bufferView), broken.gltf (an index out of
                               range), huge.glb (an image whose header claims 30000x30000)

two.gltf: 3 nodes (the third reuses mesh 0), 2 meshes, 4 primitives (indexed TRIANGLES,
a TRIANGLE_STRIP, a TRIANGLE_FAN, POINTS: 2 + 2 + 2 + 0 triangles), 2 materials (one
textured, one BLEND double-sided), 1 texture, 1 perspective camera, 1 KHR_lights_punctual
point light, and an unknown optional extension (a warning, as are the points).
"""
import json
import shutil
import struct
import sys

png = open(sys.argv[1], 'rb').read()
shutil.copyfile(sys.argv[1], 'tex.png')

pos = struct.pack('<12f', -1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0)
uv = struct.pack('<8f', 0, 1, 1, 1, 1, 0, 0, 0)
idx = struct.pack('<6H', 0, 1, 2, 0, 2, 3)
buf = pos + uv + idx


def model(images, buffer_views, buffers):
    return {
        "asset": {"version": "2.0", "generator": "softpbr make_gltf.py"},
        "extensionsUsed": ["KHR_lights_punctual", "EXT_made_up"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "name": "bulb", "intensity": 10}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3, 4]}],
        "nodes": [{"mesh": 0, "name": "quad"}, {"mesh": 1, "translation": [3, 0, 0]}, {"mesh": 0, "translation": [0, 3, 0]},
                  {"camera": 0, "translation": [0, 0, 8]},
                  {"translation": [0, 2, 4], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
        "cameras": [{"type": "perspective", "name": "front", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100}}],
        "meshes": [
            {"name": "quads", "primitives": [
                {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0},
                {"attributes": {"POSITION": 0}, "mode": 5, "material": 1}]},
            {"name": "fan", "primitives": [
                {"attributes": {"POSITION": 0}, "mode": 6},
                {"attributes": {"POSITION": 0}, "mode": 0}]}],
        "materials": [{"name": "textured", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
                      {"name": "glass", "alphaMode": "BLEND", "doubleSided": True,
                       "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 1, 0.5]}}],
        "textures": [{"source": 0, "name": "albedo"}],
        "images": images,
        "buffers": buffers,
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                        {"buffer": 0, "byteOffset": 80, "byteLength": 12}] + buffer_views,
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                      {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    }


open('two.bin', 'wb').write(buf)
open('two.gltf', 'w').write(json.dumps(model([{"uri": "tex.png"}], [], [{"uri": "two.bin", "byteLength": len(buf)}])))


def glb(name, image_bytes, edit=None):
    body = buf + b'\0' * ((4 - len(buf) % 4) % 4)
    offset = len(body)
    body += image_bytes + b'\0' * ((4 - len(image_bytes) % 4) % 4)
    g = model([{"bufferView": 3, "mimeType": "image/png"}], [{"buffer": 0, "byteOffset": offset, "byteLength": len(image_bytes)}],
              [{"byteLength": len(body)}])
    if edit:
        edit(g)
    js = json.dumps(g).encode()
    js += b' ' * ((4 - len(js) % 4) % 4)
    out = struct.pack('<III', 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(body))
    out += struct.pack('<II', len(js), 0x4E4F534A) + js + struct.pack('<II', len(body), 0x004E4942) + body
    open(name, 'wb').write(out)


glb('two.glb', png)
# 30000x30000 in the IHDR chunk (the rest of the PNG as it was): refused before decoding.
glb('huge.glb', png[:16] + struct.pack('>II', 30000, 30000) + png[24:])

broken = json.loads(open('two.gltf').read())
broken["accessors"][2]["count"] = 6
broken["bufferViews"][2]["byteLength"] = 12
open('broken.gltf', 'w').write(json.dumps(broken).replace('"indices": 2', '"indices": 0', 1))
