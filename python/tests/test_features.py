"""The features that landed after the first bindings, from Python: MSAA, image-based lighting
(the built-in studio and an .exr file; intensity, rotation, background), orthographic cameras
and glTF models (.gltf and .glb). Each renders bit for bit as the command renders the same
scene file or model."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import numpy
import pytest

import softpbr

W, H = 96, 64

# The spheres of a small scene: an edge-heavy subject for MSAA, shiny and rough for lighting.
BASE = {
    "camera": {"position": [0, 1.2, 3.2], "target": [0, 0.4, 0], "fov": 40},
    "lights": [{"type": "point", "position": [2, 3, 2], "intensity": 15}],
    "objects": [
        {"mesh": {"type": "uv_sphere", "radius": 0.45, "segments": 24, "rings": 12},
         "material": {"preset": "gold", "roughness": 0.2}, "transform": {"translate": [-0.5, 0.45, 0]}},
        {"mesh": {"type": "cube", "size": 0.7}, "material": {"base_color": [0.2, 0.5, 0.8], "roughness": 0.6},
         "transform": {"translate": [0.55, 0.35, 0], "rotate": [0, 30, 0]}},
        {"mesh": {"type": "plane", "width": 5, "depth": 5}, "material": "white_paint"},
    ],
    "render": {"width": W, "height": H},
}


def scene_with(**parts):
    scene = json.loads(json.dumps(BASE))
    for key, value in parts.items():
        if key == "render":
            scene["render"].update(value)
        else:
            scene[key] = value
    return scene


def cli_render(cli, scene, tmp_path, *args, name="scene", png_only=False):
    """The command's PNG and EXR of `scene` (a dict, written to a file, or a path) as arrays
    (the EXR None with png_only)."""
    if isinstance(scene, dict):
        path = tmp_path / f"{name}.json"
        path.write_text(json.dumps(scene))
    else:
        path = scene
    png, exr = tmp_path / f"{name}.png", tmp_path / f"{name}.exr"
    outputs = ["-o", str(png)] + ([] if png_only else ["-o", str(exr)])
    subprocess.run([cli, "render", str(path), *outputs, "-q", *map(str, args)], check=True)
    return softpbr.load_image(png), None if png_only else softpbr.load_image(exr)


def cli_msaa_exr(cli, path, tmp_path, *args):
    """The command's .exr of a multisampled render (the samples' linear box resolve)."""
    exr = tmp_path / "msaa.exr"
    subprocess.run([cli, "render", str(path), "-o", str(exr), "-q", *map(str, args)], check=True)
    return softpbr.load_image(exr)


def assert_msaa_hdr_is_the_box_resolve(cli, scene, tmp_path, hdr):
    """render_hdr of a multisampled `scene` (a dict, exposure 0) is the library's box resolve:
    the command's .exr bit for bit; and its PNG with the linear resolve (raster::resolve_box),
    no tone map and gamma 1 is, code for code, these floats through the same 255 thresholds
    ((k + 0.5) / 255, float)."""
    path = tmp_path / "msaa.json"
    path.write_text(json.dumps(scene))
    assert_same(hdr, cli_msaa_exr(cli, path, tmp_path))
    linear = json.loads(json.dumps(scene))
    linear["render"].update({"resolve": "linear", "tonemap": "none", "gamma": 1})
    path.write_text(json.dumps(linear))
    out = tmp_path / "linear.png"
    subprocess.run([cli, "render", str(path), "-o", str(out), "-q"], check=True)
    png = softpbr.load_image(out)
    thresholds = ((numpy.arange(255) + 0.5) / 255.0).astype(numpy.float32)
    codes = numpy.searchsorted(thresholds, hdr[..., :3], side="right").astype(numpy.uint8)
    differ = numpy.any(codes != png[..., :3], axis=-1)
    assert not differ.any(), f"{differ.sum()} pixels differ, the first at {numpy.argwhere(differ)[0]}"
    # Not a single sample plane: the edges hold averages, so the image is not the 1-sample one.
    assert hdr.shape == exr_shape(scene)


def exr_shape(scene):
    return (scene["render"]["height"], scene["render"]["width"], 4)


def bits(a):
    return a.view(numpy.uint32)


def assert_same(image, expected):
    assert image.shape == expected.shape and image.dtype == expected.dtype
    if image.dtype == numpy.float32:
        assert numpy.array_equal(bits(image), bits(expected)), softpbr.compare(image, expected).describe()
    else:
        assert numpy.array_equal(image, expected), softpbr.compare(image, expected).describe()


# ---- MSAA ------------------------------------------------------------------------------------

def test_a_dict_scene_with_msaa_renders_as_the_command(cli, tmp_path):
    scene = scene_with(render={"msaa": 4})
    png, _ = cli_render(cli, scene, tmp_path, png_only=True)
    assert_same(softpbr.render(scene), png)
    assert_msaa_hdr_is_the_box_resolve(cli, scene, tmp_path, softpbr.render_hdr(scene))
    assert not softpbr.render_hdr(scene).flags.owndata  # the resolved target's buffer, not a copy
    # Antialiased: not the 1-sample image, in 8 bits or in float.
    assert not numpy.array_equal(softpbr.render(scene), softpbr.render(scene_with()))
    assert not numpy.array_equal(softpbr.render_hdr(scene), softpbr.render_hdr(scene_with()))


@pytest.mark.parametrize("samples", [4, 8])
def test_the_msaa_keyword_is_the_msaa_option(cli, tmp_path, samples):
    png, _ = cli_render(cli, scene_with(), tmp_path, "--msaa", samples, "--exposure", 0.5, png_only=True)
    assert_same(softpbr.render(scene_with(), msaa=samples, exposure=0.5), png)
    assert_msaa_hdr_is_the_box_resolve(cli, scene_with(render={"msaa": samples}), tmp_path,
                                       softpbr.render_hdr(scene_with(), msaa=samples))
    # The keyword overrides the scene's render.msaa, both ways.
    assert_same(softpbr.render(scene_with(render={"msaa": 8 if samples == 4 else 4}), msaa=samples), softpbr.render(
        scene_with(render={"msaa": samples})))
    assert_same(softpbr.render(scene_with(render={"msaa": samples}), msaa=1), softpbr.render(scene_with()))
    assert_same(softpbr.render_hdr(scene_with(render={"msaa": samples}), msaa=1), softpbr.render_hdr(scene_with()))


def test_msaa_on_a_scene_object_and_the_linear_resolve(cli, tmp_path):
    scene = softpbr.Scene.from_dict(scene_with())
    scene.msaa, scene.resolve = 4, "linear"
    assert (scene.msaa, scene.resolve) == (4, "linear")
    png, _ = cli_render(cli, scene_with(render={"msaa": 4, "resolve": "linear"}), tmp_path, png_only=True)
    assert_same(softpbr.render(scene), png)
    scene.resolve = "tonemapped"
    assert not numpy.array_equal(softpbr.render(scene), png)  # bright edges resolve differently


def test_bad_sample_counts_are_value_errors():
    with pytest.raises(ValueError, match=r"^msaa: expected 1, 4 or 8, got 3$"):
        softpbr.render(scene_with(), msaa=3)
    with pytest.raises(ValueError, match=r"^msaa: expected 1, 4 or 8, got 2$"):
        softpbr.render_hdr(scene_with(), msaa=2)
    with pytest.raises(ValueError, match=r"^msaa: expected 1, 4 or 8, got 0$"):
        softpbr.Scene().msaa = 0
    with pytest.raises(ValueError, match=r"^resolve: expected \"tonemapped\" or \"linear\""):
        softpbr.Scene().resolve = "box"
    with pytest.raises(ValueError, match=r"^<dict>: /render/msaa: "):
        softpbr.render(scene_with(render={"msaa": 2}))


# ---- Environments ----------------------------------------------------------------------------

def equirect(path: Path) -> Path:
    """A small equirectangular .exr: a warm sky above a dark ground, a bright spot (a sun)."""
    h, w = 16, 32
    v = (numpy.arange(h, dtype=numpy.float32)[:, None] + 0.5) / h
    u = (numpy.arange(w, dtype=numpy.float32)[None, :] + 0.5) / w
    image = numpy.zeros((h, w, 4), numpy.float32)
    sky = numpy.clip(1.0 - 2.0 * v, 0.0, 1.0)
    image[..., 0] = 0.2 + 1.2 * sky + 0.1 * u
    image[..., 1] = 0.15 + 0.9 * sky
    image[..., 2] = 0.1 + 0.6 * sky + 0.3 * (1 - u)
    image[3, 20, :3] = 40.0
    image[..., 3] = 1.0
    softpbr.write_hdr(path, image, exr=True)
    return path


def test_a_dict_scene_with_the_studio_environment_and_msaa_renders_as_the_command(cli, tmp_path):
    scene = scene_with(environment={"intensity": 1.5, "rotation": 60}, render={"msaa": 4})
    png, _ = cli_render(cli, scene, tmp_path, png_only=True)
    image = softpbr.render(scene)
    assert_same(image, png)
    assert_msaa_hdr_is_the_box_resolve(cli, scene, tmp_path, softpbr.render_hdr(scene))
    assert not numpy.array_equal(image, softpbr.render(scene_with(render={"msaa": 4})))


def test_a_scene_lit_in_python_renders_as_its_file(cli, tmp_path):
    sky = equirect(tmp_path / "sky.exr")
    for spec, call in [
        ({}, lambda s: s.set_environment("studio")),
        ({"intensity": 2, "rotation": 90}, lambda s: s.set_environment(softpbr.Environment.studio(), intensity=2, rotation=90)),
        ({"file": str(sky), "intensity": 0.75, "rotation": -45, "background": "blur", "blur": 0.5},
         lambda s: s.set_environment(softpbr.Environment.load(sky), intensity=0.75, rotation=-45, background="blur", blur=0.5)),
        ({"file": str(sky), "background": [0.1, 0.2, 0.3], "multiscatter": False},
         lambda s: s.set_environment(sky, background=(0.1, 0.2, 0.3), multiscatter=False)),
        ({"occlusion": False}, lambda s: s.set_environment("studio", occlusion=False)),
        ({"file": str(sky), "background": "transparent"}, lambda s: s.set_environment(str(sky), background="transparent")),
    ]:
        scene = softpbr.Scene.from_dict(scene_with())
        call(scene)
        png, exr = cli_render(cli, scene_with(environment=spec), tmp_path)
        assert_same(softpbr.render(scene), png)
        assert_same(softpbr.render_hdr(scene), exr)
        assert_same(softpbr.render(scene_with(environment=spec)), png)
    assert png[0, 0, 3] == 0  # transparent


def test_set_environment_on_a_loaded_scene_is_the_env_options(cli, tmp_path):
    # softpbr render scene.json --env sky.exr --env-intensity 3 --env-rotation 30
    sky = equirect(tmp_path / "sky.exr")
    path = tmp_path / "plain.json"
    path.write_text(json.dumps(scene_with()))
    png, exr = cli_render(cli, path, tmp_path, "--env", sky, "--env-intensity", 3, "--env-rotation", 30)
    scene = softpbr.Scene.load(path)
    scene.set_environment(sky, intensity=3, rotation=30)
    assert_same(softpbr.render(scene), png)
    assert_same(softpbr.render_hdr(scene), exr)
    # --occlusion off is occlusion=False.
    png, _ = cli_render(cli, path, tmp_path, "--env", sky, "--occlusion", "off", png_only=True)
    off = softpbr.Scene.load(path)
    off.set_environment(sky, occlusion=False)
    assert not off.occlusion
    assert_same(softpbr.render(off), png)
    # ... and the properties say what it is; None takes it away again.
    assert scene.environment == softpbr.Environment.load(sky)  # cached by content: the same map
    assert (scene.environment_intensity, scene.environment_rotation, scene.background_mode) == (3, 30, "environment")
    scene.environment_intensity, scene.environment_rotation = 1, 0
    scene.set_environment(None)
    assert scene.environment is None and scene.background_mode == "color"
    assert_same(softpbr.render(scene), softpbr.render(scene_with()))


def test_environment_properties_render_as_the_file(tmp_path):
    scene = softpbr.Scene.from_dict(scene_with())
    scene.set_environment("studio")
    scene.environment_intensity, scene.environment_rotation = 0.5, 120
    scene.background_mode, scene.background_blur, scene.multiscatter = "blur", 0.8, False
    assert scene.occlusion
    scene.occlusion = False
    spec = {"intensity": 0.5, "rotation": 120, "background": "blur", "blur": 0.8, "multiscatter": False, "occlusion": False}
    assert_same(softpbr.render(scene), softpbr.render(scene_with(environment=spec)))
    assert softpbr.Scene.from_dict(scene_with(environment=spec)).environment == softpbr.Environment.studio()
    env = softpbr.Environment.studio()
    assert env.size > 0 and env.bytes > 0 and "studio" in repr(env)


def test_environment_errors(tmp_path):
    scene = softpbr.Scene()
    with pytest.raises(ValueError, match=r"^intensity: expected a number in \[0, 1e\+06\], got -1$"):
        scene.set_environment("studio", intensity=-1)
    assert scene.environment is None  # nothing changed
    with pytest.raises(ValueError, match=r"^blur: expected a number in \[0, 1\], got 2$"):
        scene.set_environment("studio", blur=2)
    with pytest.raises(ValueError, match=r"^background: expected \"environment\", \"blur\", \"transparent\""):
        scene.set_environment("studio", background="sky")
    with pytest.raises(ValueError, match="the scene has no environment"):
        scene.background_mode = "blur"
    with pytest.raises(ValueError, match=r"^environment_rotation: expected a number"):
        scene.environment_rotation = float("nan")
    with pytest.raises(FileNotFoundError):
        softpbr.Environment.load(tmp_path / "missing.hdr")
    with pytest.raises(FileNotFoundError):
        scene.set_environment(tmp_path / "missing.exr")
    bad = tmp_path / "bad.hdr"
    bad.write_bytes(b"not an image")
    with pytest.raises(ValueError, match="bad.hdr"):
        softpbr.Environment.load(bad)
    with pytest.raises(ValueError, match=r"^Environment.load: environment size 7"):
        softpbr.Environment.load(equirect(tmp_path / "sky.exr"), size=7)
    with pytest.raises(TypeError, match="^environment: expected an Environment"):
        scene.set_environment(3)
    with pytest.raises(ValueError, match=r"^<dict>: /environment/intensity: "):
        softpbr.render(scene_with(environment={"intensity": -2}))


# ---- Orthographic cameras --------------------------------------------------------------------

@pytest.mark.parametrize("ortho", [{"ymag": 1.1}, {"ymag": 0.8, "xmag": 1.6}])
def test_an_orthographic_camera_renders_as_the_file(cli, tmp_path, ortho):
    spec = {"position": [2, 2.5, 3], "target": [0, 0.3, 0], "orthographic": ortho, "near": 0, "far": 20}
    png, exr = cli_render(cli, scene_with(camera=spec), tmp_path)
    scene = softpbr.Scene.from_dict(scene_with())
    scene.camera = softpbr.Camera(position=(2, 2.5, 3), target=(0, 0.3, 0), orthographic=True, near=0, far=20, **ortho)
    assert_same(softpbr.render(scene), png)
    assert_same(softpbr.render_hdr(scene), exr)
    camera = softpbr.Scene.from_dict(scene_with(camera=spec)).camera
    assert camera.orthographic and camera.ymag == pytest.approx(ortho["ymag"])
    assert camera.xmag == pytest.approx(ortho.get("xmag", 0.0)) and "orthographic" in repr(camera)
    scene.camera = softpbr.Camera(position=(2, 2.5, 3), target=(0, 0.3, 0))
    assert not scene.camera.orthographic
    assert not numpy.array_equal(softpbr.render(scene), png)


def test_a_bad_orthographic_camera_is_a_value_error():
    scene = softpbr.Scene.from_dict(scene_with())
    scene.camera = softpbr.Camera(orthographic=True, ymag=0)
    with pytest.raises(ValueError, match="ymag"):
        softpbr.render(scene)


# ---- glTF models -----------------------------------------------------------------------------

def models(source_dir):
    return [source_dir / "fuzz" / "corpus" / "gltf" / "meshopt.glb",  # .glb, EXT_meshopt_compression
            source_dir / "fuzz" / "corpus" / "gltf" / "draco.glb",  # .glb, KHR_draco_mesh_compression
            source_dir / "examples" / "viewer" / "tests" / "boxes.gltf"]


def test_glb_models_render_as_the_command(cli, source_dir, tmp_path):
    for model in models(source_dir):
        png, exr = cli_render(cli, model, tmp_path, "--width", 80, "--height", 48, name=model.stem)
        image = softpbr.render(model, width=80, height=48)
        assert image[..., :3].max() > 20, model
        assert_same(image, png)
        assert_same(softpbr.render_hdr(model, width=80, height=48), exr)


def test_glb_options_are_the_command_options(cli, source_dir, tmp_path):
    model = source_dir / "examples" / "viewer" / "tests" / "boxes.gltf"
    sky = equirect(tmp_path / "sky.exr")
    cases = [
        (("--env", "none"), lambda: softpbr.Scene.load_gltf(model, width=80, height=48, environment=False), {}),
        (("--msaa", 4, "--yaw", -40), lambda: softpbr.Scene.load_gltf(model, width=80, height=48, yaw=-40), {"msaa": 4}),
        (("--env", sky, "--env-intensity", 2, "--env-rotation", 45),
         lambda: with_env(softpbr.Scene.load_gltf(model, width=80, height=48), sky, 2, 45), {}),
    ]
    for args, scene, keywords in cases:
        png, exr = cli_render(cli, model, tmp_path, "--width", 80, "--height", 48, *args, name="boxes",
                              png_only="--msaa" in args)
        assert_same(softpbr.render(scene(), **keywords), png)
        if "--msaa" in args:
            exr = cli_msaa_exr(cli, model, tmp_path, "--width", 80, "--height", 48, *args)
        assert_same(softpbr.render_hdr(scene(), **keywords), exr)
    lit = softpbr.Scene.load_gltf(model, width=80, height=48)
    assert lit.environment == softpbr.Environment.studio() and lit.background_mode == "blur"
    rig = softpbr.Scene.load_gltf(model, width=80, height=48, environment=False)
    assert rig.environment is None and len(rig.lights) == 3


def with_env(scene, path, intensity, rotation):
    scene.set_environment(path, intensity=intensity, rotation=rotation)
    return scene


def khronos_sample(source_dir, name):
    """A Khronos sample model of ../shared/gltf (SOFTPBR_SHARED_GLTF), its .glb or .gltf; skips
    when it is not there (the samples are optional)."""
    shared = Path(os.environ.get("SOFTPBR_SHARED_GLTF", source_dir.parent / "shared" / "gltf"))
    for sub, ext in [("glTF-Binary", ".glb"), ("glTF", ".gltf")]:
        model = shared / name / sub / (name + ext)
        if model.is_file():
            return model
    pytest.skip(f"{shared / name} is not here (the Khronos samples are optional)")


@pytest.mark.parametrize("name", ["Box", "MetalRoughSpheresNoTextures", "TextureTransformTest", "TwoSidedPlane"])
def test_a_khronos_sample_model_renders_as_the_command(cli, source_dir, tmp_path, name):
    model = khronos_sample(source_dir, name)
    png, exr = cli_render(cli, model, tmp_path, "--width", 64, "--height", 48, name="sample")
    assert_same(softpbr.render(model, width=64, height=48), png)
    assert_same(softpbr.render_hdr(model, width=64, height=48), exr)
    png, _ = cli_render(cli, model, tmp_path, "--width", 64, "--height", 48, "--msaa", 4, name="sample", png_only=True)
    assert_same(softpbr.render(model, width=64, height=48, msaa=4), png)


def test_a_gltf_models_objects_added_to_a_scene_render_as_the_model(source_dir):
    for model in models(source_dir) + [source_dir / "fuzz" / "corpus" / "gltf" / "triangle.gltf"]:
        shown = softpbr.Scene.load_gltf(model, width=80, height=48)
        loaded = softpbr.load_gltf(model)
        assert len(loaded.objects) == len(shown.objects) > 0 and loaded.triangles == shown.triangles
        scene = softpbr.Scene()
        scene.camera, scene.lights = shown.camera, loaded.lights
        scene.ambient, scene.background = shown.ambient, shown.background
        scene.set_environment("studio", background="blur")
        for o in loaded.objects:
            scene.add(o.mesh, o.material, o.transform)
        assert_same(softpbr.render(scene, width=80, height=48), softpbr.render(model, width=80, height=48))
    assert "0 cameras" in repr(loaded) and loaded.cameras == [] and loaded.camera_names == []
    assert loaded.objects[0].material.textured  # the fixture's texture came along


def test_load_gltf_errors(tmp_path, source_dir):
    with pytest.raises(FileNotFoundError):
        softpbr.load_gltf(tmp_path / "missing.glb")
    bad = tmp_path / "bad.gltf"
    bad.write_text('{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], '
                   '"meshes": [{"primitives": [{"attributes": {"POSITION": 3}}]}]}')
    with pytest.raises(ValueError, match=r"bad.gltf: /meshes/0/primitives/0/attributes/POSITION: accessor 3 does not exist$"):
        softpbr.load_gltf(bad)
    with pytest.raises(ValueError, match="scene: expected an index >= 0"):
        softpbr.load_gltf(models(source_dir)[0], scene=-2)


def test_a_gltf_orthographic_camera_is_the_commands_camera_option(cli, source_dir, tmp_path):
    gltf = json.loads((source_dir / "examples" / "viewer" / "tests" / "boxes.gltf").read_text())
    gltf["cameras"] = [{"name": "side", "type": "orthographic",
                        "orthographic": {"xmag": 2.0, "ymag": 1.25, "znear": 0.1, "zfar": 30}}]
    gltf["nodes"].append({"camera": 0, "translation": [1, 1.5, 6], "rotation": [-0.0998334, 0, 0, 0.9950042]})
    gltf["scenes"][0]["nodes"].append(len(gltf["nodes"]) - 1)
    model = tmp_path / "ortho.gltf"
    model.write_text(json.dumps(gltf))
    png, exr = cli_render(cli, model, tmp_path, "--width", 80, "--height", 50, "--camera", 0, name="ortho")
    scene = softpbr.Scene.load_gltf(model, width=80, height=50, camera=0)
    assert scene.camera.orthographic and (scene.camera.xmag, scene.camera.ymag) == (2.0, 1.25)
    assert_same(softpbr.render(scene), png)
    assert_same(softpbr.render_hdr(scene), exr)
    loaded = softpbr.load_gltf(model)
    assert loaded.camera_names == ["side"] and loaded.cameras[0].orthographic
    # The same camera built in Python renders the same bits.
    again = softpbr.Scene.load_gltf(model, width=80, height=50)
    c = loaded.cameras[0]
    again.camera = softpbr.Camera(position=c.position, target=c.target, up=c.up, near=c.near, far=c.far,
                                  orthographic=True, ymag=c.ymag, xmag=c.xmag)
    assert_same(softpbr.render(again), png)


# ---- KHR_materials_variants ------------------------------------------------------------------

def test_a_material_variant_renders_as_the_command_and_an_unknown_one_lists_them(cli, source_dir, tmp_path):
    model = khronos_sample(source_dir, "MaterialsVariantsShoe")
    png, _ = cli_render(cli, model, tmp_path, "--width", 64, "--height", 48, "--variant", "beach", name="beach", png_only=True)
    beach = softpbr.render(model, width=64, height=48, variant="beach")
    assert_same(beach, png)
    assert_same(softpbr.render(model, width=64, height=48, variant="1"), beach)  # by index
    assert not numpy.array_equal(beach, softpbr.render(model, width=64, height=48, variant="street"))
    # The default material of every primitive is the first variant's ("midnight").
    assert_same(softpbr.render(model, width=64, height=48), softpbr.render(model, width=64, height=48, variant="midnight"))
    loaded = softpbr.load_gltf(model, variant="street")
    assert len(loaded.objects) == 1
    with pytest.raises(ValueError, match='no variant "red" \\(the variants: 0 "midnight", 1 "beach", 2 "street"\\)'):
        softpbr.render(model, width=64, height=48, variant="red")
    with pytest.raises(ValueError, match="variant: a glTF model's setting"):
        softpbr.render(source_dir / "examples" / "scenes" / "lights.json", variant="beach")


# ---- Shadows ---------------------------------------------------------------------------------

def test_the_shadows_keyword_is_the_shadows_option(cli, tmp_path):
    # BASE's point light, then the same with "shadows": true in the file.
    shadowed = scene_with(lights=[{"type": "point", "position": [2, 3, 2], "intensity": 15, "shadows": True}])
    png, _ = cli_render(cli, scene_with(), tmp_path, "--shadows", "on", png_only=True)
    assert_same(softpbr.render(scene_with(), shadows=True), png)
    assert_same(softpbr.render(shadowed), png)
    # The shadows show: the plane behind the sphere and the cube is darker.
    assert not numpy.array_equal(softpbr.render(shadowed), softpbr.render(scene_with()))
    # shadows=False turns a file's shadows off; None keeps them.
    assert_same(softpbr.render(shadowed, shadows=False), softpbr.render(scene_with()))
    assert_same(softpbr.render_hdr(shadowed, shadows=False), softpbr.render_hdr(scene_with()))
    off, _ = cli_render(cli, shadowed, tmp_path, "--shadows", "off", name="off", png_only=True)
    assert_same(off, softpbr.render(scene_with()))


def test_the_ground_keyword_is_the_ground_option(cli, tmp_path):
    # BASE without its floor plane: the ground goes under the sphere and the cube.
    floating = scene_with(objects=BASE["objects"][:2], render={"background": [0, 0, 0, 0]})
    grounded = dict(floating, ground={"shadow": True})
    png, _ = cli_render(cli, floating, tmp_path, "--ground", "shadow", png_only=True)
    assert_same(softpbr.render(floating, ground="shadow"), png)
    assert_same(softpbr.render(grounded), png)
    # The shadow shows, as alpha over the transparent background.
    plain = softpbr.render(floating)
    assert numpy.count_nonzero(png[..., 3]) > numpy.count_nonzero(plain[..., 3])
    # "none" removes a file's ground; None keeps it.
    assert_same(softpbr.render(grounded, ground="none"), plain)
    with pytest.raises(ValueError, match="ground: expected shadow or none"):
        softpbr.render(floating, ground="soft")


# ---- Glass --------------------------------------------------------------------------------

def test_glass_renders_as_the_command(cli, tmp_path):
    # examples/scenes/glass.json: transmission, roughness, volume attenuation.
    glass = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "scenes", "glass.json")
    png, exr = cli_render(cli, glass, tmp_path, "--width", 200, "--height", 160)
    assert_same(softpbr.render(glass, width=200, height=160), png)
    assert_same(softpbr.render_hdr(glass, width=200, height=160), exr)
    # The same cubes made opaque (transmission 0) look different: the glass is seen through.
    with open(glass) as f:
        scene = json.load(f)
    for o in scene["objects"]:
        o.get("material", {}).pop("transmission", None)
    opaque = softpbr.render(scene, width=200, height=160, base_dir=os.path.dirname(glass))
    assert not numpy.array_equal(opaque, png)
