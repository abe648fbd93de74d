"""Golden-image checks for pytest (or any test runner), on softpbr's golden library.

    from softpbr.testing import assert_image_matches
    assert_image_matches(softpbr.render("scene.json"), "goldens/scene.png")

Exact by default. On failure the actual image, the heat-map diff and the side-by-side image
are written next to the golden (``scene.actual.png``, ``scene.diff.png``,
``scene.side-by-side.png``) and an ``ImageMismatch`` (an AssertionError) is raised whose
message holds the statistics and whose ``comparison`` attribute holds them as numbers.
Update mode (``pytest --softpbr-update-goldens``, or ``SOFTPBR_UPDATE_GOLDENS=1`` as for the
C++ checks) rewrites goldens that are missing or out of tolerance instead of failing.
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


__all__ = ["ImageMismatch", "assert_image_matches", "update_mode", "UPDATE_COMMAND"]
