"""softpbr.testing.assert_model_matches golden-tests an exporter: the model a (toy) glTF
exporter writes must look like the reference model, from every view, bit for bit; a file
that is written differently but looks the same passes, a real regression fails and names the
view that shows it and what changed in the file."""

from __future__ import annotations

import base64
import json
import struct
from pathlib import Path

import pytest

import softpbr
from softpbr.testing import ModelMismatch, assert_model_matches

# A pyramid on a square base: the exporter's input (positions, triangles, an sRGB colour).
POSITIONS = [(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1), (0, 1.5, 0)]
TRIANGLES = [(0, 1, 2), (0, 2, 3), (3, 2, 4), (2, 1, 4), (1, 0, 4), (0, 3, 4)]
COLOUR_SRGB = (200, 120, 40)


def srgb_to_linear(c: float) -> float:
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def export(path: Path, *, embed: bool = False, wide_indices: bool = False, linearize: bool = True,
           flip_winding: bool = False) -> Path:
    """The exporter under test: flat-shaded triangles (each its own three vertices and face
    normal) to glTF. The options that must not change the look: embed (a data URI instead of
    a .bin file), wide_indices (uint32). The bugs it may have: linearize=False (the sRGB
    colour written as if linear), flip_winding (faces turned inside out)."""
    pos, nrm = b"", b""
    for tri in TRIANGLES:
        a, b, c = (POSITIONS[i] for i in (tri if not flip_winding else (tri[0], tri[2], tri[1])))
        u = [b[k] - a[k] for k in range(3)]
        v = [c[k] - a[k] for k in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        length = sum(x * x for x in n) ** 0.5
        for p in (a, b, c):
            pos += struct.pack("<3f", *p)
            nrm += struct.pack("<3f", *(x / length for x in n))
    count = 3 * len(TRIANGLES)
    idx = struct.pack(f"<{count}{'I' if wide_indices else 'H'}", *range(count))
    idx += b"\0" * (-len(idx) % 4)
    blob = pos + nrm + idx
    colour = [srgb_to_linear(c / 255) if linearize else c / 255 for c in COLOUR_SRGB] + [1.0]
    if embed:
        uri = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
    else:
        uri = path.with_suffix(".bin").name
        path.with_suffix(".bin").write_bytes(blob)
    gltf = {
        "asset": {"version": "2.0", "generator": "toy exporter"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": colour, "metallicFactor": 0, "roughnessFactor": 0.6}}],
        "buffers": [{"byteLength": len(blob), "uri": uri}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
                        {"buffer": 0, "byteOffset": len(pos), "byteLength": len(nrm)},
                        {"buffer": 0, "byteOffset": 2 * len(pos), "byteLength": count * (4 if wide_indices else 2)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
                       "min": [-1, 0, -1], "max": [1, 1.5, 1]},
                      {"bufferView": 1, "componentType": 5126, "count": count, "type": "VEC3"},
                      {"bufferView": 2, "componentType": 5125 if wide_indices else 5123, "count": count,
                       "type": "SCALAR"}],
    }
    path.write_text(json.dumps(gltf, sort_keys=embed))
    return path


@pytest.fixture
def reference(tmp_path: Path) -> Path:
    # In a real suite this file is checked in (the exporter's approved output); here the
    # exporter's default output stands for it.
    return export(tmp_path / "reference.gltf")


@pytest.mark.parametrize("options", [{"embed": True}, {"wide_indices": True}, {"embed": True, "wide_indices": True}])
def test_an_export_written_differently_looks_the_same(tmp_path, reference, options):
    exported = export(tmp_path / "exported.gltf", **options)
    assert exported.read_bytes() != reference.read_bytes()
    results = assert_model_matches(reference, exported, width=96, height=96)
    assert len(results) == 8  # the default views: front, ring, top
    assert all(c.identical for _, c in results)


def test_a_colour_space_bug_fails_in_every_view_and_names_the_material(tmp_path, reference):
    exported = export(tmp_path / "exported.gltf", linearize=False)
    with pytest.raises(ModelMismatch) as failure:
        assert_model_matches(reference, exported, width=96, height=96, output_dir=tmp_path / "failures")
    e = failure.value
    assert all(c.pixels_above > 0 for _, c in e.views)
    assert any(prop == "object 0 material" for prop, _, _ in e.changes)
    assert "8 of 8 views differ" in str(e)
    assert len(e.written) == 8 and all(p.is_file() for p in e.written)
    sheet = softpbr.load_image(e.written[0])
    assert sheet.shape == (96, 3 * 96, 4)


def test_inside_out_faces_fail_and_a_tolerance_does_not_hide_them(tmp_path, reference):
    exported = export(tmp_path / "exported.gltf", flip_winding=True)
    with pytest.raises(ModelMismatch):
        assert_model_matches(reference, exported, max_diff=8, max_pixels=50, width=96, height=96)


def test_the_view_that_shows_a_change_is_the_worst(tmp_path):
    # Only the back (−z) half moves: seen from behind (yaw 180) it differs most, from the
    # front not at all at pitch 0 — the base and the front faces are unchanged.
    reference = export(tmp_path / "reference.gltf")
    global POSITIONS
    saved = POSITIONS
    try:
        POSITIONS = [(-1, 0, -1.3), (1, 0, -1.3), (1, 0, 1), (-1, 0, 1), (0, 1.5, 0)]
        exported = export(tmp_path / "exported.gltf")
    finally:
        POSITIONS = saved
    with pytest.raises(ModelMismatch) as failure:
        assert_model_matches(reference, exported, yaws=[0, 180], pitches=[0], width=96, height=96)
    front, back = failure.value.views
    assert back[1].pixels_above > front[1].pixels_above
    assert "worst: view 1, yaw 180" in str(failure.value)


def test_bad_input_is_a_value_error_naming_the_file(tmp_path, reference):
    broken = tmp_path / "broken.gltf"
    broken.write_text("{not json")
    with pytest.raises(ValueError, match="broken.gltf"):
        assert_model_matches(reference, broken)
    with pytest.raises(FileNotFoundError):
        assert_model_matches(reference, tmp_path / "missing.glb")
    with pytest.raises(ValueError, match="views"):
        assert_model_matches(reference, reference, views=0)
