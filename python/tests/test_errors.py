"""Errors are Python exceptions with the library's one-line messages: ValueError for bad
values (the JSON pointer for dict scenes), OSError for files that cannot be read."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys

import numpy
import pytest

import softpbr


def small(scene):
    return {"objects": [], **scene, "render": {"width": 16, "height": 16}}


def test_a_bad_value_in_a_dict_scene_names_its_json_pointer(scenes):
    scene = json.loads((scenes / "gallery.json").read_text())
    scene["objects"][3]["material"]["roughness"] = 2
    with pytest.raises(ValueError) as e:
        softpbr.render(scene)
    assert str(e.value) == "<dict>: /objects/3/material/roughness: expected a number in [0, 1], got 2"


def test_a_dict_scene_gets_the_same_message_as_its_file(scenes, tmp_path):
    scene = {"objects": [{"mesh": {"type": "uv_sphere", "radius": -1}}]}
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(scene))
    with pytest.raises(ValueError) as from_file:
        softpbr.render(path)
    with pytest.raises(ValueError) as from_dict:
        softpbr.render(scene)
    assert str(from_file.value).startswith(str(path) + ": /objects/0/mesh/radius: ")
    assert str(from_dict.value) == str(from_file.value).replace(str(path), "<dict>", 1)


@pytest.mark.parametrize("value, text", [(float("nan"), "nan"), (float("inf"), "inf")])
def test_a_non_finite_number_in_a_dict_names_its_pointer(value, text):
    scene = {"lights": [{"type": "point", "position": [0, 1, value]}]}
    with pytest.raises(ValueError, match=rf"^<dict>: /lights/0/position/2: expected a finite number, got {text}$"):
        softpbr.render(scene)


def test_a_misspelt_key_is_refused_with_a_suggestion():
    with pytest.raises(ValueError, match=r"^<dict>: /cmaera: "):
        softpbr.render({"cmaera": {}})


def test_unreadable_files_are_oserrors(tmp_path):
    with pytest.raises(FileNotFoundError):
        softpbr.render(tmp_path / "missing.json")
    with pytest.raises(IsADirectoryError):
        softpbr.render(tmp_path)
    with pytest.raises(FileNotFoundError):
        softpbr.load_obj(tmp_path / "missing.obj")
    with pytest.raises(FileNotFoundError):
        softpbr.load_image(tmp_path / "missing.png")


def test_invalid_files_are_valueerrors(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text("{\"camera\": [1, 2")
    with pytest.raises(ValueError, match="^" + re.escape(str(bad)) + ": "):
        softpbr.render(bad)
    obj = tmp_path / "bad.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nf 1 2 3\n")
    with pytest.raises(ValueError, match=re.escape(str(obj))):
        softpbr.load_obj(obj)
    png = tmp_path / "bad.png"
    png.write_bytes(b"\x89PNG\r\n\x1a\nnot really")
    with pytest.raises(ValueError, match=re.escape(str(png))):
        softpbr.load_image(png)


@pytest.mark.parametrize("options, message", [
    ({"width": 0}, r"^width: expected a value in \[1, 16384\], got 0$"),
    ({"height": 20000}, r"^height: expected a value in \[1, 16384\], got 20000$"),
    ({"tile_size": 7}, r"^tile_size: expected an even size in \[8, 4096\], got 7$"),
    ({"tonemap": "filmic"}, r'^tonemap: expected one of none, reinhard, aces, neutral, got "filmic"$'),
    ({"exposure": 100.0}, r"^exposure: expected a value in \[-64, 64\], got 100$"),
    ({"gamma": 0.05}, r"^gamma: expected 0 \(the sRGB curve\) or a number in \[0\.1, 10\], got 0\.05$"),
    ({"threads": 2000}, r"^threads: expected a value in \[0, 1024\], got 2000$"),
])
def test_bad_render_options_are_valueerrors(options, message):
    with pytest.raises(ValueError, match=message):
        softpbr.render(small({}), **options)


def test_a_scene_value_set_out_of_range_is_refused_when_it_renders():
    # The scene's own settings are checked with the same messages as the keyword arguments.
    scene = softpbr.Scene.from_dict(small({}))
    scene.tile_size = 7
    with pytest.raises(ValueError, match=r"^tile_size: expected an even size in \[8, 4096\], got 7$"):
        softpbr.render(scene)


def test_other_scene_types_are_typeerrors():
    with pytest.raises(TypeError, match="expected a path, a dict or a softpbr.Scene, got int"):
        softpbr.render(3)


def test_an_unknown_preset_lists_the_presets():
    with pytest.raises(ValueError, match=r'unknown preset "unobtainium" \(expected one of gold, '):
        softpbr.Material.preset("unobtainium")


def test_an_invalid_material_is_refused_when_rendered():
    scene = softpbr.Scene()
    scene.width = scene.height = 16
    scene.add(softpbr.Mesh.cube(), softpbr.Material(roughness=3))
    with pytest.raises(ValueError, match="roughness"):
        softpbr.render(scene)


@pytest.mark.parametrize("name, call", [
    ("pipe.png", "softpbr.load_image(p)"),
    ("pipe.hdr", "softpbr.Environment.load(p)"),
    ("pipe.gltf", "softpbr.load_gltf(p)"),
    ("pipe.glb", "softpbr.Scene.load_gltf(p)"),
    ("pipe.obj", "softpbr.load_obj(p)"),
    ("pipe.json", "softpbr.render(p)"),
])
def test_a_named_pipe_is_refused_at_once_not_waited_on(tmp_path, name, call):
    # A FIFO with no writer: opening it blocked forever, holding the GIL. In a child process
    # with a deadline, so that a regression fails instead of hanging the suite.
    fifo = tmp_path / name
    os.mkfifo(fifo)
    code = f"import softpbr\np = {str(fifo)!r}\ntry:\n    {call}\nexcept OSError as e:\n    print('OSError:', e)\n"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert result.stdout == f"OSError: {fifo}: is a named pipe (FIFO), not a regular file\n", result.stderr


@pytest.mark.parametrize("frame", [-1, 10_000_000, 2**40])
def test_a_frame_outside_the_commands_range_is_refused(frame):
    message = r"^frame: expected a frame in \[0, 9999999\], got " + str(frame) + "$"
    with pytest.raises(ValueError, match=message):
        softpbr.render(small({}), frame=frame)
    with pytest.raises(ValueError, match=message):
        softpbr.render_hdr(small({}), frame=frame)


def test_the_last_frame_of_the_commands_range_renders():
    assert softpbr.render(small({}), frame=9_999_999).shape == (16, 16, 4)


def test_missing_images_warn_leaves_a_texture_out_that_error_refuses(cli, tmp_path, source_dir):
    # A model downloaded without its texture: refused by default, its texture left out with a
    # warning with missing_images="warn", as the command's --missing-images warn.
    subprocess.run([sys.executable, str(source_dir / "cli/tests/make_gltf.py"), str(source_dir / "cli/tests/goldens/lights.png")],
                   cwd=tmp_path, check=True)
    gone = tmp_path / "gone.gltf"
    gone.write_text((tmp_path / "two.gltf").read_text().replace('"tex.png"', '"gone.png"'))
    with pytest.raises(ValueError, match=re.escape(f"/images/0/uri: {tmp_path / 'gone.png'}: no such file")):
        softpbr.load_gltf(gone)
    model = softpbr.load_gltf(gone, missing_images="warn")
    assert any(w.endswith("gone.png: no such file (a missing image: its textures are left out)") for w in model.warnings)
    with pytest.raises(ValueError, match="no such file"):
        softpbr.Scene.load_gltf(gone, width=32, height=24)
    scene = softpbr.Scene.load_gltf(gone, width=32, height=24, missing_images="warn")
    expected = tmp_path / "expected.png"
    subprocess.run([cli, "render", str(gone), "-o", str(expected), "--width", "32", "--height", "24",
                    "--missing-images", "warn", "-q"], check=True, capture_output=True)
    assert numpy.array_equal(softpbr.render(scene), softpbr.load_image(expected))
    with pytest.raises(ValueError, match='missing_images: expected error or warn, got "maybe"'):
        softpbr.load_gltf(gone, missing_images="maybe")
