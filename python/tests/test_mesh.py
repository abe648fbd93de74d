"""Meshes from numpy arrays: the same renders as the same mesh read from an OBJ file, and
bad arrays refused with the documented errors (TypeError for a dtype, ValueError for a
shape, a NaN or infinity, a zero normal, an index out of range)."""

from __future__ import annotations

import numpy
import pytest

import softpbr

# A small closed shape (an octahedron stretched on y) whose coordinates and UVs are exact in
# binary, so the OBJ file's text reads back as the same floats (and OBJ's v flip is exact).
_P = numpy.array([[1, 0, 0], [-1, 0, 0], [0, 1.5, 0], [0, -1.5, 0], [0, 0, 1], [0, 0, -1]], numpy.float32)
_I = numpy.array([[0, 2, 4], [4, 2, 1], [1, 2, 5], [5, 2, 0], [4, 3, 0], [1, 3, 4], [5, 3, 1], [0, 3, 5]], numpy.uint32)
_UV = numpy.array([[0, 0.5], [0.5, 0.5], [0.25, 0], [0.25, 1], [0.125, 0.5], [0.375, 0.5]], numpy.float32)
# Vertices in the order the triangles first use them: the order the OBJ loader creates them in.
_ORDER = numpy.array([0, 2, 4, 1, 5, 3])
POSITIONS, UVS = _P[_ORDER], _UV[_ORDER]
INDICES = numpy.argsort(_ORDER).astype(numpy.uint32)[_I]
NORMALS = POSITIONS / numpy.linalg.norm(POSITIONS, axis=1, keepdims=True)


def with_index(indices, row, value):
    out = indices.copy()
    out[row, 1] = value
    return out


def write_obj(path, normals=None, uvs=None):
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in POSITIONS.tolist()]
    if uvs is not None:
        lines += [f"vt {u!r} {1 - v!r}" for u, v in uvs.tolist()]  # OBJ's v grows up the image
    if normals is not None:
        lines += [f"vn {x!r} {y!r} {z!r}" for x, y, z in normals.astype(numpy.float64).tolist()]
    for tri in (INDICES + 1).tolist():
        if uvs is not None and normals is not None:
            lines.append("f " + " ".join(f"{i}/{i}/{i}" for i in tri))
        else:
            lines.append("f " + " ".join(map(str, tri)))
    path.write_text("\n".join(lines) + "\n")
    return path


def render_mesh(mesh):
    scene = softpbr.Scene()
    scene.camera = softpbr.Camera(position=(1.5, 1.2, 3), target=(0, 0, 0), fov=40)
    scene.add_light(softpbr.Light.point((2, 3, 2), intensity=25))
    scene.add(mesh, softpbr.Material.preset("copper"))
    scene.width, scene.height = 64, 64
    return softpbr.render(scene, threads=2)


@pytest.mark.parametrize("with_attributes", [False, True])
def test_a_numpy_mesh_renders_as_the_same_obj(tmp_path, with_attributes):
    if with_attributes:
        mine = softpbr.Mesh(POSITIONS, INDICES, normals=NORMALS.astype(numpy.float32), uvs=UVS)
        obj = softpbr.load_obj(write_obj(tmp_path / "shape.obj", NORMALS.astype(numpy.float32), UVS))
    else:  # smooth normals computed on both sides
        mine = softpbr.Mesh(POSITIONS, INDICES)
        obj = softpbr.load_obj(write_obj(tmp_path / "shape.obj"))
    for name in ["positions", "normals", "uvs", "indices"]:
        assert numpy.array_equal(getattr(mine, name), getattr(obj, name)), name
    image = render_mesh(mine)
    assert image[..., :3].max() > 0
    assert numpy.array_equal(image, render_mesh(obj))


def test_mesh_arrays_round_trip():
    mesh = softpbr.Mesh(POSITIONS, INDICES.astype(numpy.int64), uvs=UVS)
    assert (mesh.vertex_count, mesh.triangle_count) == (6, 8)
    assert mesh.positions.dtype == numpy.float32 and numpy.array_equal(mesh.positions, POSITIONS)
    assert mesh.indices.dtype == numpy.uint32 and numpy.array_equal(mesh.indices, INDICES)
    assert numpy.allclose(numpy.linalg.norm(mesh.normals, axis=1), 1)
    # Non-contiguous views are read through their strides.
    wide = numpy.zeros((6, 6), numpy.float32)
    wide[:, ::2] = POSITIONS
    assert numpy.array_equal(softpbr.Mesh(wide[:, ::2], INDICES).positions, POSITIONS)


@pytest.mark.parametrize("args, kwargs, error, message", [
    ((POSITIONS[:, :2], INDICES), {}, ValueError, r"^Mesh: positions: expected an array of shape \(N, 3\), got \(6, 2\)$"),
    ((POSITIONS.ravel(), INDICES), {}, ValueError, r"^Mesh: positions: expected an array of shape \(N, 3\), got \(18,\)$"),
    ((POSITIONS.astype(numpy.float64), INDICES), {}, TypeError, r"^Mesh: positions: expected dtype float32, got float64"),
    ((POSITIONS, INDICES.ravel()), {}, ValueError, r"^Mesh: indices: expected an array of shape \(M, 3\)"),
    ((POSITIONS, INDICES.astype(numpy.float32)), {}, TypeError, r"^Mesh: indices: expected an integer dtype"),
    ((POSITIONS, with_index(INDICES, 3, 6)), {}, ValueError, r"^Mesh: indices\[3\]: index 6 is out of range \(6 vertices\)$"),
    ((POSITIONS, INDICES.astype(numpy.int32) - 1), {}, ValueError, r"^Mesh: indices\[0\]: index -1 is out of range"),
    ((POSITIONS, INDICES.astype(numpy.uint64) + numpy.uint64(2**63)), {}, ValueError,
     r"^Mesh: indices\[0\]: index 9223372036854775808 is out of range"),
    ((POSITIONS, INDICES), {"normals": NORMALS[:5].astype(numpy.float32)}, ValueError,
     r"^Mesh: normals: expected 6 rows \(one per position\), got 5$"),
    ((POSITIONS, INDICES), {"normals": numpy.zeros((6, 3), numpy.float32)}, ValueError,
     r"^Mesh: normals\[0\]: expected a non-zero vector"),
    ((POSITIONS, INDICES), {"uvs": UVS.astype(numpy.float16)}, TypeError, r"^Mesh: uvs: expected dtype float32, got float16"),
])
def test_bad_arrays_give_the_documented_errors(args, kwargs, error, message):
    with pytest.raises(error, match=message):
        softpbr.Mesh(*args, **kwargs)


@pytest.mark.parametrize("value, text", [(numpy.nan, "nan"), (numpy.inf, "inf"), (-numpy.inf, "-inf")])
def test_non_finite_values_name_their_row(value, text):
    bad = POSITIONS.copy()
    bad[4, 1] = value
    with pytest.raises(ValueError, match=rf"^Mesh: positions\[4\]: expected finite numbers, got {text}$"):
        softpbr.Mesh(bad, INDICES)
    uvs = UVS.copy()
    uvs[2, 0] = value
    with pytest.raises(ValueError, match=rf"^Mesh: uvs\[2\]: expected finite numbers, got {text}$"):
        softpbr.Mesh(POSITIONS, INDICES, uvs=uvs)


def test_procedural_meshes_and_bad_parameters():
    assert softpbr.Mesh.uv_sphere(1, 8, 4).triangle_count > 0
    assert softpbr.Mesh.torus().vertex_count > 0
    with pytest.raises(ValueError):
        softpbr.Mesh.uv_sphere(-1, 8, 4)


def test_nested_lists_are_converted():
    mesh = softpbr.Mesh(POSITIONS.tolist(), INDICES.tolist(), uvs=UVS.tolist())
    assert numpy.array_equal(mesh.positions, POSITIONS) and numpy.array_equal(mesh.indices, INDICES)
    with pytest.raises(TypeError, match="Mesh: positions: expected a numpy array, got str"):
        softpbr.Mesh("not a mesh", INDICES)
