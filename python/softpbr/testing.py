"""Golden-image checks for pytest (or any test runner), on softpbr's golden library.

    from softpbr.testing import assert_image_matches
    assert_image_matches(softpbr.render("scene.json"), "goldens/scene.png")

Exact by default. On failure the actual image, the heat-map diff and the side-by-side image
are written next to the golden (``scene.actual.png``, ``scene.diff.png``,
``scene.side-by-side.png``) and an ``ImageMismatch`` (an AssertionError) is raised whose
message holds the statistics and whose ``comparison`` attribute holds them as numbers.
Update mode (``pytest --softpbr-update-goldens``, or ``SOFTPBR_UPDATE_GOLDENS=1`` as for the
C++ checks) rewrites goldens that are missing or out of tolerance instead of failing.

Two models (an exporter's output against a reference model, an optimized file against its
source) are compared by their look, as ``softpbr diff a.glb b.glb`` compares them:

    from softpbr.testing import assert_model_matches
    assert_model_matches("reference.glb", "exported.glb")

Both are rendered from the same views (the automatic camera's front, a ring and the top),
framed on the union of their bounds; a ``ModelMismatch`` names the worst view and what
changed in the files, and writes each differing view's side-by-side image to
``output_dir`` when one is given.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import List, Optional, Union

import numpy

from . import _softpbr

# Set by the pytest plugin's --softpbr-update-goldens; the environment variable also counts.
update_goldens = False

UPDATE_COMMAND = "pytest --softpbr-update-goldens (or SOFTPBR_UPDATE_GOLDENS=1)"


def update_mode() -> bool:
    """Whether goldens are being rewritten: --softpbr-update-goldens or SOFTPBR_UPDATE_GOLDENS=1."""
    return update_goldens or os.environ.get("SOFTPBR_UPDATE_GOLDENS") == "1"


class ImageMismatch(AssertionError):
    """An image differs from its golden. ``comparison`` (a softpbr.Comparison, zero when the
    golden could not be read), ``golden`` and ``written`` (the failure images) say how."""

    def __init__(self, message: str, comparison: "_softpbr.Comparison", golden: Path, written: List[Path]):
        super().__init__(message)
        self.comparison = comparison
        self.golden = golden
        self.written = written


def assert_image_matches(image: numpy.ndarray, golden_path: Union[str, "os.PathLike[str]"], max_diff: float = 0,
                         max_pixels: int = 0, *, update: Optional[bool] = None) -> "_softpbr.MatchResult":
    """Checks ``image`` (uint8 against a .png golden, float32 against a .hdr golden) against
    the golden file: passes when at most ``max_pixels`` pixels have a channel differing by
    more than ``max_diff`` and the sizes agree. Returns the match result; raises
    ImageMismatch otherwise (after writing the failure images next to the golden)."""
    golden = Path(golden_path).absolute()
    result = _softpbr.match_golden(image, golden, max_diff=max_diff, max_pixels=max_pixels, output_dir=golden.parent,
                                   update=update_mode() if update is None else update, update_command=UPDATE_COMMAND)
    if not result.passed:
        raise ImageMismatch(result.message, result.comparison, golden, [Path(p) for p in result.written])
    return result


class ModelMismatch(AssertionError):
    """Two models look different. ``views`` holds, per view, its (yaw, pitch) and its
    softpbr.Comparison; ``changes`` the (property, expected, actual) rows of what differs in
    the files; ``written`` the side-by-side images written."""

    def __init__(self, message: str, views: List[tuple], changes: List[tuple], written: List[Path]):
        super().__init__(message)
        self.views = views
        self.changes = changes
        self.written = written


def assert_model_matches(expected: Union[str, "os.PathLike[str]"], actual: Union[str, "os.PathLike[str]"],
                         max_diff: float = 0, max_pixels: int = 0, *, views: int = 8,
                         yaws: Optional[List[float]] = None, pitches: Optional[List[float]] = None, width: int = 256,
                         height: int = 256, output_dir: Optional[Union[str, "os.PathLike[str]"]] = None,
                         ) -> List[tuple]:
    """Checks that the model ``actual`` looks like ``expected`` (.gltf, .glb, .obj or scene
    files): each view passes when at most ``max_pixels`` pixels have a channel differing by
    more than ``max_diff`` (8-bit codes). Returns [((yaw, pitch), Comparison)] per view;
    raises ModelMismatch otherwise (after writing ``view<N>.side-by-side.png`` into
    ``output_dir`` for each differing view, when given)."""
    r = _softpbr.render_model_views(os.fspath(expected), os.fspath(actual), views=views, yaws=list(yaws or []),
                                    pitches=list(pitches or []), width=width, height=height)
    results = [(v, _softpbr.compare(a, b, max_diff)) for v, a, b in zip(r["views"], r["expected"], r["actual"])]
    failing = [i for i, (_, c) in enumerate(results) if c.pixels_above > max_pixels]
    if not failing:
        return results
    of_actual = dict(r["actual_summary"])
    of_expected = dict(r["expected_summary"])
    changes = [(k, v, of_actual.get(k, "(none)")) for k, v in r["expected_summary"] if of_actual.get(k) != v]
    changes += [(k, "(none)", v) for k, v in r["actual_summary"] if k not in of_expected]
    written: List[Path] = []
    if output_dir is not None:
        folder = Path(output_dir)
        folder.mkdir(parents=True, exist_ok=True)
        for i in failing:
            path = folder / f"view{i}.side-by-side.png"
            _softpbr.write_png(path, _softpbr.side_by_side(r["expected"][i], r["actual"][i]))
            written.append(path)
    worst = max(failing, key=lambda i: (results[i][1].pixels_above, results[i][1].max))
    (yaw, pitch), c = results[worst]
    message = (f"{os.fspath(actual)} does not look like {os.fspath(expected)}: {len(failing)} of {len(results)} views "
               f"differ (worst: view {worst}, yaw {yaw:g}, pitch {pitch:g}: {c.pixels_above} pixels over {max_diff:g}, "
               f"allowed {max_pixels}; largest difference {c.max:g})")
    if changes:
        message += "\nchanged in the files:\n" + "\n".join(f"  {k}: {a} -> {b}" for k, a, b in changes[:20])
    if written:
        message += "\nwritten: " + ", ".join(str(p) for p in written)
    raise ModelMismatch(message, results, changes, written)


__all__ = ["ImageMismatch", "ModelMismatch", "assert_image_matches", "assert_model_matches", "update_mode",
           "UPDATE_COMMAND"]
