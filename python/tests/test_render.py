"""Renders from Python are the library's renders: bit-identical to the command's output for
the same scene file, a dict scene equal to its file, the gallery golden through
assert_image_matches, and images returned without a copy."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import numpy
import pytest

import softpbr

W, H = 160, 90  # small: the suite runs in CI's budget


def run_cli(cli, *args):
    subprocess.run([cli, "render", *map(str, args), "-q"], check=True)


def test_render_is_bit_identical_to_the_command(cli, scenes, tmp_path):
    for name in ["gallery.json", "lights.json", "textured.json"]:
        png, exr = tmp_path / (name + ".png"), tmp_path / (name + ".exr")
        run_cli(cli, scenes / name, "-o", png, "-o", exr, "--width", W, "--height", H)
        image = softpbr.render(scenes / name, width=W, height=H)
        assert image.shape == (H, W, 4) and image.dtype == numpy.uint8
        assert numpy.array_equal(image, softpbr.load_image(png)), name
        hdr = softpbr.render_hdr(scenes / name, width=W, height=H)
        assert hdr.shape == (H, W, 4) and hdr.dtype == numpy.float32
        assert numpy.array_equal(hdr.view(numpy.uint32), softpbr.load_image(exr).view(numpy.uint32)), name


def test_overrides_are_the_command_options(cli, scenes, tmp_path):
    png, exr = tmp_path / "lights.png", tmp_path / "lights.exr"
    run_cli(cli, scenes / "lights.json", "-o", png, "-o", exr, "--width", 96, "--height", 64, "--tonemap", "aces",
            "--exposure", 1.5, "--threads", 1, "--tile-size", 8)
    image = softpbr.render(scenes / "lights.json", width=96, height=64, tonemap="aces", exposure=1.5, threads=3,
                           tile_size=32)
    assert numpy.array_equal(image, softpbr.load_image(png))
    hdr = softpbr.render_hdr(scenes / "lights.json", width=96, height=64, exposure=1.5, threads=2, tile_size=16)
    assert numpy.array_equal(hdr.view(numpy.uint32), softpbr.load_image(exr).view(numpy.uint32))


def test_a_dict_scene_renders_as_its_file(scenes):
    scene = json.loads((scenes / "gallery.json").read_text())
    from_dict = softpbr.render(scene, width=W, height=H)
    assert numpy.array_equal(from_dict, softpbr.render(scenes / "gallery.json", width=W, height=H))
    assert numpy.array_equal(softpbr.render(softpbr.Scene.from_dict(scene), width=W, height=H), from_dict)


def test_a_dict_scene_resolves_files_against_base_dir(scenes):
    scene = {"camera": {"position": [0, 1, 3], "target": [0, 0.3, 0]},
             "lights": [{"type": "point", "position": [2, 3, 2], "intensity": 20}],
             "objects": [{"mesh": {"file": "models/podium.obj", "fit": 1}}],
             "render": {"width": 64, "height": 48}}
    image = softpbr.render(scene, base_dir=scenes)
    assert image.shape == (48, 64, 4) and image[..., :3].max() > 0
    with pytest.raises(ValueError, match=r"^<dict>: /objects/0/mesh/file: "):
        softpbr.render(scene)  # the working directory has no models/podium.obj


def test_the_gallery_golden_matches(source_dir, scenes):
    # gallery.json is pbr::make_gallery() exactly; the library's golden is 640x360.
    image = softpbr.render(scenes / "gallery.json", width=640, height=360)
    result = softpbr.testing.assert_image_matches(image, source_dir / "tests" / "goldens" / "gallery.png")
    assert result.passed and result.comparison.identical


def test_frames_of_the_turntable_differ_and_frame_0_is_the_file(scenes):
    first = softpbr.render(scenes / "turntable.json", width=64, height=48)
    assert numpy.array_equal(first, softpbr.render(scenes / "turntable.json", width=64, height=48, frame=0))
    assert not numpy.array_equal(first, softpbr.render(scenes / "turntable.json", width=64, height=48, frame=30))


def test_images_come_back_without_a_copy(scenes):
    for image in (softpbr.render(scenes / "gallery.json", width=32, height=18),
                  softpbr.render_hdr(scenes / "gallery.json", width=32, height=18)):
        assert not image.flags.owndata and image.base is not None  # a view of the C++ buffer
        assert image.flags.c_contiguous and image.flags.writeable


def test_a_scene_built_in_python_renders_as_the_same_scene_file(tmp_path):
    spec = {"camera": {"position": [0, 1.5, 4], "target": [0, 0.5, 0], "fov": 45},
            "lights": [{"type": "point", "position": [2, 3, 2], "intensity": 20},
                       {"type": "directional", "direction": [-1, -1, -1], "intensity": 0.5}],
            "objects": [{"mesh": {"type": "uv_sphere", "radius": 0.5, "segments": 32, "rings": 16},
                         "material": {"preset": "gold", "roughness": 0.25},
                         "transform": {"translate": [0, 0.5, 0]}},
                        {"mesh": {"type": "plane", "width": 6, "depth": 6}, "material": "white_paint"}],
            "render": {"width": 80, "height": 60}}
    scene = softpbr.Scene()
    scene.camera = softpbr.Camera(position=(0, 1.5, 4), target=(0, 0.5, 0), fov=45)
    scene.add_light(softpbr.Light.point((2, 3, 2), intensity=20))
    scene.add_light(softpbr.Light.directional((-1, -1, -1), intensity=0.5))
    gold = softpbr.Material.preset("gold")
    gold.roughness = 0.25
    move = numpy.eye(4, dtype=numpy.float32)
    move[1, 3] = 0.5
    scene.add(softpbr.Mesh.uv_sphere(0.5, 32, 16), gold, move)
    scene.add(softpbr.Mesh.plane(6, 6), softpbr.Material.preset("white_paint"))
    scene.width, scene.height = 80, 60
    assert numpy.array_equal(softpbr.render(scene), softpbr.render(spec))
    assert numpy.array_equal(scene.objects[0].transform, move)


def test_the_readme_example_draws_its_image(source_dir, tmp_path, monkeypatch):
    readme = (source_dir / "README.md").read_text()
    start = readme.index("```python\n", readme.index("## From Python")) + len("```python\n")
    code = readme[start:readme.index("```\n", start)]
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "README.md (From Python)", "exec"), {})
    image = softpbr.load_image(tmp_path / "spheres.png")
    softpbr.testing.assert_image_matches(image, source_dir / "docs" / "images" / "python_spheres.png")


def test_a_gltf_model_renders_as_the_command_frames_it(cli, source_dir, tmp_path):
    model = source_dir / "fuzz" / "corpus" / "gltf" / "triangle.gltf"  # the hand-written fixture: textured, MASK, double-sided
    for args, scene in [((), lambda: model),
                        (("--yaw", 30, "--pitch", 15), lambda: softpbr.Scene.load_gltf(model, width=72, height=40, yaw=30, pitch=15))]:
        png = tmp_path / "model.png"
        run_cli(cli, model, "-o", png, "--width", 72, "--height", 40, *args)
        image = softpbr.render(scene(), width=72, height=40)
        assert image[..., :3].max() > 20
        assert numpy.array_equal(image, softpbr.load_image(png)), args
    with pytest.raises(ValueError, match="has 0 cameras, no camera 2"):
        softpbr.Scene.load_gltf(model, camera=2)
    # The view is checked with the render job's messages, as the command's --width, --camera, --pitch.
    with pytest.raises(ValueError, match=r"^Scene\.load_gltf: width: expected a value in \[1, 16384\], got 0$"):
        softpbr.Scene.load_gltf(model, width=0)
    with pytest.raises(ValueError, match=r"^Scene\.load_gltf: camera: expected an index >= 0, got -1$"):
        softpbr.Scene.load_gltf(model, camera=-1)
    with pytest.raises(ValueError, match=r"^Scene\.load_gltf: pitch: expected degrees in \[-89, 89\], got 95$"):
        softpbr.Scene.load_gltf(model, pitch=95)


def test_an_animated_gltf_model_at_a_time_renders_as_the_command_renders_it(cli, source_dir, tmp_path):
    shared = Path(os.environ.get("SOFTPBR_SHARED", source_dir.parent / "shared"))
    model = shared / "gltf" / "InterpolationTest" / "glTF-Binary" / "InterpolationTest.glb"
    if not model.is_file():
        pytest.skip(f"{model} is absent")
    still = softpbr.render(softpbr.Scene.load_gltf(model, width=80, height=60), width=80, height=60)
    for args, kwargs in [(("--time", 0.3), {"time": 0.3}),
                         (("--time", 0.3, "--animation", "Linear Translation"), {"time": 0.3, "animation": "Linear Translation"}),
                         (("--time", 0.3, "--animation", 8), {"time": 0.3, "animation": 8})]:
        png = tmp_path / "moment.png"
        run_cli(cli, model, "-o", png, "--width", 80, "--height", 60, *args)
        image = softpbr.render(softpbr.Scene.load_gltf(model, width=80, height=60, **kwargs), width=80, height=60)
        assert numpy.array_equal(image, softpbr.load_image(png)), args
        assert not numpy.array_equal(image, still), args
    with pytest.raises(ValueError, match='no animation is named "Walk"'):
        softpbr.Scene.load_gltf(model, time=1.0, animation="Walk")


def test_a_gltf_scene_chosen_by_index_renders_as_the_command_renders_it(cli, source_dir, tmp_path):
    shared = Path(os.environ.get("SOFTPBR_SHARED", source_dir.parent / "shared"))
    model = shared / "gltf" / "MultipleScenes" / "glTF" / "MultipleScenes.gltf"
    if not model.is_file():
        pytest.skip(f"{model} is absent")
    default = softpbr.render(softpbr.Scene.load_gltf(model, width=80, height=60), width=80, height=60)
    png = tmp_path / "scene0.png"
    run_cli(cli, model, "-o", png, "--width", 80, "--height", 60, "--scene", 0)
    image = softpbr.render(softpbr.Scene.load_gltf(model, width=80, height=60, scene=0), width=80, height=60)
    assert numpy.array_equal(image, softpbr.load_image(png))
    assert not numpy.array_equal(image, default)
    with pytest.raises(ValueError, match=r'no scene "left" \(the scenes: 0, 1\)'):
        softpbr.Scene.load_gltf(model, scene="left")
