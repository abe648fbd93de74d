#!/usr/bin/env python3
"""glTF models for `softpbr diff A B` of models (cli/tests/driver.sh, groups model_diff and
thumbnail), written into the current folder:

  cube.gltf        a unit cube (cube.bin): the four sides and the top in material 0 (grey),
                   the back face (-z) a primitive of its own in material 1 (grey too)
  cube_copy.gltf   the same JSON written again with its keys in another order: the same model
  cube_back.gltf   material 1's baseColorFactor changed to red: only views that see the back
                   face (yaw 180) differ
  cube_moved.gltf  the node moved 0.25 along +x: every view differs
  cube.glb         cube.gltf in one binary file (for the thumbnailer)
"""
import copy
import json
import struct

# The cube's faces: (normal, four corners counter-clockwise seen from outside).
FACES = [
    ((0, 0, 1), [(-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]),
    ((1, 0, 0), [(1, -1, 1), (1, -1, -1), (1, 1, -1), (1, 1, 1)]),
    ((-1, 0, 0), [(-1, -1, -1), (-1, -1, 1), (-1, 1, 1), (-1, 1, -1)]),
    ((0, 1, 0), [(-1, 1, 1), (1, 1, 1), (1, 1, -1), (-1, 1, -1)]),
    ((0, -1, 0), [(-1, -1, -1), (1, -1, -1), (1, -1, 1), (-1, -1, 1)]),
    ((0, 0, -1), [(1, -1, -1), (-1, -1, -1), (-1, 1, -1), (1, 1, -1)]),  # the back face: primitive 1
]


def buffers():
    pos, nrm, idx = b'', b'', b''
    for n, (normal, corners) in enumerate(FACES):
        for c in corners:
            pos += struct.pack('<3f', *(0.5 * x for x in c))
            nrm += struct.pack('<3f', *normal)
        base = 4 * (n % 5) if n < 5 else 0
        idx += struct.pack('<6H', base, base + 1, base + 2, base, base + 2, base + 3)
    return pos, nrm, idx


pos, nrm, idx = buffers()
blob = pos + nrm + idx  # positions (24 × 12), normals (24 × 12), indices (5 faces × 12, then 12)
front_pos, back_pos = 20 * 12, 4 * 12


def model(uri=None):
    buffer = {"byteLength": len(blob)}
    if uri:
        buffer["uri"] = uri
    return {
        "asset": {"version": "2.0", "generator": "softpbr make_diff_models.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "cube"}],
        "meshes": [{"name": "cube", "primitives": [
            {"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 4, "material": 0},
            {"attributes": {"POSITION": 2, "NORMAL": 3}, "indices": 5, "material": 1}]}],
        "materials": [
            {"name": "sides", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.6, 1], "metallicFactor": 0,
                                                       "roughnessFactor": 0.5}},
            {"name": "back", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.6, 1], "metallicFactor": 0,
                                                      "roughnessFactor": 0.5}}],
        "buffers": [buffer],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": front_pos},
            {"buffer": 0, "byteOffset": 24 * 12, "byteLength": front_pos},
            {"buffer": 0, "byteOffset": front_pos, "byteLength": back_pos},
            {"buffer": 0, "byteOffset": 24 * 12 + front_pos, "byteLength": back_pos},
            {"buffer": 0, "byteOffset": 48 * 12, "byteLength": 5 * 12},
            {"buffer": 0, "byteOffset": 48 * 12 + 5 * 12, "byteLength": 12}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 20, "type": "VEC3", "min": [-0.5] * 3, "max": [0.5] * 3},
            {"bufferView": 1, "componentType": 5126, "count": 20, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-0.5, -0.5, -0.5],
             "max": [0.5, 0.5, -0.5]},
            {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 4, "componentType": 5123, "count": 30, "type": "SCALAR"},
            {"bufferView": 5, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    }


def write(name, m, **dump):
    with open(name, 'w') as f:
        json.dump(m, f, **dump)


open('cube.bin', 'wb').write(blob)
base = model('cube.bin')
write('cube.gltf', base, indent=1)
write('cube_copy.gltf', base, sort_keys=True)
back = copy.deepcopy(base)
back["materials"][1]["pbrMetallicRoughness"]["baseColorFactor"] = [0.9, 0.1, 0.1, 1]
write('cube_back.gltf', back)
moved = copy.deepcopy(base)
moved["nodes"][0]["translation"] = [0.25, 0, 0]
write('cube_moved.gltf', moved)

# The binary container: header, JSON chunk (padded with spaces), BIN chunk (zeros).
js = json.dumps(model()).encode()
js += b' ' * (-len(js) % 4)
bin_chunk = blob + b'\0' * (-len(blob) % 4)
glb = struct.pack('<III', 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(bin_chunk))
glb += struct.pack('<II', len(js), 0x4E4F534A) + js + struct.pack('<II', len(bin_chunk), 0x004E4942) + bin_chunk
open('cube.glb', 'wb').write(glb)
