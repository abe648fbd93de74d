"""softpbr: bit-exact physically based rendering on the CPU, from Python.

    import softpbr
    image = softpbr.render("examples/scenes/gallery.json", width=320, height=180)
    image.shape, image.dtype            # (180, 320, 4) uint8, sRGB-encoded RGBA

``render`` and ``render_hdr`` take a scene file's path, a dict with the scene-file schema
(docs/scene-format.md) or a ``Scene``; they release the GIL while C++ renders, so renders in
several Python threads run at the same time, and Ctrl-C stops a render between tiles.
``compare``, ``diff_image`` and ``softpbr.testing.assert_image_matches`` come from the golden
library. Errors: ValueError with the library's one-line message (the JSON pointer for a
scene), TypeError for an array of the wrong dtype, OSError for a file that cannot be read.
See docs/python.md.
"""

from __future__ import annotations

import os
from typing import Any, Mapping, Optional, Union

import numpy

from ._softpbr import (
    Camera,
    Comparison,
    Environment,
    GltfModel,
    Light,
    Material,
    MatchResult,
    Mesh,
    Object,
    Scene,
    active_renders,
    compare,
    content_hash,
    diff_image,
    load_gltf,
    load_image,
    match_golden,
    side_by_side,
    write_hdr,
    write_png,
)
from . import _softpbr
from . import testing
from ._scene_dict import scene_json

__version__ = "0.1.0"

SceneLike = Union[str, "os.PathLike[str]", Mapping[str, Any], Scene]


def _scene_from_dict(scene: Mapping[str, Any], base_dir: Union[str, "os.PathLike[str]", None] = None,
                     name: str = "<dict>") -> Scene:
    """A Scene from a dict with the scene-file schema: the same validation and messages as a
    file, named ``name`` ("<dict>: /objects/0/material/roughness: expected a number in [0, 1],
    got 2"). Relative paths resolve against ``base_dir`` (default: the working directory)."""
    return Scene.from_json(scene_json(scene, name), name, os.fspath(base_dir) if base_dir is not None else ".")


Scene.from_dict = staticmethod(_scene_from_dict)  # type: ignore[attr-defined]


def load_scene(scene: SceneLike, *, base_dir: Union[str, "os.PathLike[str]", None] = None,
               width: Optional[int] = None, height: Optional[int] = None, variant: Optional[str] = None) -> Scene:
    """A Scene from a path, a dict (see Scene.from_dict) or a Scene (returned as is). A glTF
    model (.gltf, .glb) is framed for a width x height image (default 1280x720) and lit by
    the studio environment as ``softpbr render model.glb`` shows it (Scene.load_gltf), with
    its material variant ``variant`` (KHR_materials_variants: a name or an index, as
    ``--variant``) when given; ValueError for a variant with any other scene."""
    if variant is not None and not (isinstance(scene, (str, os.PathLike))
                                    and os.fspath(scene).lower().endswith((".gltf", ".glb"))):
        raise ValueError("variant: a glTF model's setting; in a scene file, a glTF object gives its own \"variant\"")
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return _scene_from_dict(scene, base_dir)
    if isinstance(scene, (str, os.PathLike)):
        path = os.fspath(scene)
        if path.lower().endswith((".gltf", ".glb")):
            return Scene.load_gltf(path, width=width or 1280, height=height or 720, variant=variant)
        return Scene.load(path)
    raise TypeError(f"scene: expected a path, a dict or a softpbr.Scene, got {type(scene).__name__}")


def render(scene: SceneLike, *, width: Optional[int] = None, height: Optional[int] = None, threads: Optional[int] = None,
           tile_size: Optional[int] = None, tonemap: Optional[str] = None, exposure: Optional[float] = None,
           gamma: Optional[float] = None, msaa: Optional[int] = None, frame: int = 0,
           base_dir: Union[str, "os.PathLike[str]", None] = None, variant: Optional[str] = None,
           shadows: Optional[bool] = None, ground: Optional[str] = None) -> numpy.ndarray:
    """Renders ``scene`` to a (height, width, 4) uint8 array: tone mapped, sRGB (or gamma)
    encoded, the bytes ``softpbr render scene.json -o out.png`` writes. ``scene`` is a scene
    file's path, a glTF model's (framed automatically), a dict with the scene-file schema or
    a Scene.

    Keyword arguments override the scene's render block as the command's options do:
    width, height (1..16384), threads (0 = all cores; the image is the same for any),
    tile_size, tonemap ("none", "reinhard", "aces", "neutral"), exposure (stops), gamma
    (0 = exact sRGB), msaa (samples a pixel: 1, 4 or 8, as ``--msaa``). ``frame`` picks a
    frame of the scene's turntable animation. ``variant`` shows a glTF model's material
    variant (KHR_materials_variants), by name or index, as ``--variant``. ``shadows``:
    True (every light casts shadows), False (none does) or None (as the scene says: a glTF
    model's lights cast them, a scene file's where ``"shadows": true``), as ``--shadows``.
    ``ground``: "shadow" (a shadow catcher under the objects: their soft contact shadow and
    the lights' shadows, black with the shadow as alpha), "none" or None (as the scene
    says), as ``--ground``.
    The GIL is released while rendering; Ctrl-C raises KeyboardInterrupt from here.
    """
    return _softpbr.render(load_scene(scene, base_dir=base_dir, width=width, height=height, variant=variant), width=width, height=height, threads=threads,
                           tile_size=tile_size, tonemap=tonemap, exposure=exposure, gamma=gamma, msaa=msaa, frame=frame,
                           shadows=shadows, ground=ground)


def render_hdr(scene: SceneLike, *, width: Optional[int] = None, height: Optional[int] = None, threads: Optional[int] = None,
               tile_size: Optional[int] = None, exposure: Optional[float] = None, msaa: Optional[int] = None,
               frame: int = 0, base_dir: Union[str, "os.PathLike[str]", None] = None,
               variant: Optional[str] = None, shadows: Optional[bool] = None,
               ground: Optional[str] = None) -> numpy.ndarray:
    """Renders ``scene`` to a (height, width, 4) float32 array of linear colour x 2^exposure
    (what ``.exr`` output holds; with MSAA the samples' linear average, the box filter),
    without a copy of the render target's colour buffer."""
    return _softpbr.render_hdr(load_scene(scene, base_dir=base_dir, width=width, height=height, variant=variant), width=width, height=height, threads=threads,
                               tile_size=tile_size, exposure=exposure, msaa=msaa, frame=frame, shadows=shadows,
                               ground=ground)


def translate(x: float, y: float, z: float) -> numpy.ndarray:
    """A 4x4 float32 translation matrix, for Scene.add(mesh, material, transform)."""
    m = numpy.eye(4, dtype=numpy.float32)
    m[:3, 3] = (x, y, z)
    return m


def load_obj(path: Union[str, "os.PathLike[str]"]) -> Mesh:
    """All shapes of an OBJ file as one Mesh (Mesh.load_obj)."""
    return Mesh.load_obj(os.fspath(path))


__all__ = [
    "Camera", "Comparison", "Environment", "GltfModel", "Light", "Material", "MatchResult", "Mesh", "Object", "Scene", "SceneLike",
    "active_renders", "compare", "content_hash", "diff_image", "load_gltf", "load_image", "load_obj", "load_scene",
    "match_golden", "render", "render_hdr", "side_by_side", "translate", "write_hdr", "write_png",
]
