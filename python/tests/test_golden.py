"""compare, diff_image and softpbr.testing.assert_image_matches (the golden library from
Python): statistics, failure images written next to the golden, update mode by option and
by environment variable."""

from __future__ import annotations

import math
import os
import shutil
import subprocess
import sys
import textwrap

import numpy
import pytest

import softpbr
from softpbr.testing import ImageMismatch, assert_image_matches


def gradient(w=8, h=4):
    image = numpy.zeros((h, w, 4), numpy.uint8)
    image[..., 0] = numpy.arange(w, dtype=numpy.uint8)[None, :] * 16
    image[..., 1] = numpy.arange(h, dtype=numpy.uint8)[:, None] * 32
    image[..., 3] = 255
    return image


def test_compare_gives_the_statistics():
    a = gradient()
    same = softpbr.compare(a, a.copy())
    assert same.identical and same.max == 0 and math.isinf(same.psnr) and same.pixels == 32
    b = a.copy()
    b[1, 2, 0] += 10
    b[3, 5, 2] += 3
    c = softpbr.compare(a, b, max_diff=5)
    assert not c.identical and c.max == 10 and list(c.max_per_channel) == [10, 0, 3, 0]
    assert c.pixels_above == 1 and c.fraction_above == 1 / 32
    assert c.mean == pytest.approx(13 / (32 * 4))
    assert c.rmse == pytest.approx(math.sqrt((100 + 9) / 128))
    assert c.psnr == pytest.approx(20 * math.log10(255 / c.rmse))
    assert "1 of 32 pixels" in str(c)
    bigger = softpbr.compare(a, gradient(9, 4))
    assert not bigger.same_size and bigger.expected_size == (8, 4) and bigger.actual_size == (9, 4)


def test_float_images_compare_in_their_units():
    a = numpy.full((2, 3, 4), 0.5, numpy.float32)
    b = a.copy()
    b[0, 0, 1] = 0.75
    c = softpbr.compare(a, b)
    assert c.max == 0.25 and c.peak == 1 and c.pixels_above == 1
    with pytest.raises(TypeError, match="one dtype"):
        softpbr.compare(a, gradient())


def test_diff_image_is_a_heat_map():
    a = gradient()
    b = a.copy()
    b[2, 3, 1] += 40
    heat = softpbr.diff_image(a, b)
    assert heat.shape == a.shape and heat.dtype == numpy.uint8
    assert tuple(heat[2, 3]) == (255, 255, 255, 255)  # the largest difference shows white
    assert heat[..., :3].sum() == 3 * 255  # everything else black
    assert softpbr.side_by_side(a, b).shape == (4, 24, 4)
    with pytest.raises(ValueError, match=r"shape \(height, width, 4\)"):
        softpbr.diff_image(a[..., :3], b[..., :3])


def test_a_changed_scene_fails_its_golden_and_writes_the_images(source_dir, scenes, tmp_path):
    golden = tmp_path / "gallery.png"
    shutil.copy(source_dir / "tests" / "goldens" / "gallery.png", golden)
    scene = softpbr.Scene.load(scenes / "gallery.json")
    scene.exposure = 0.5  # brighter than the golden
    image = softpbr.render(scene, width=640, height=360)
    with pytest.raises(ImageMismatch) as e:
        assert_image_matches(image, golden, update=False)
    assert isinstance(e.value, AssertionError)
    message = str(e.value)
    assert "PSNR" in message and "RMSE" in message and "pixels" in message
    c = e.value.comparison
    assert c.same_size and c.max > 0 and 0 < c.pixels_above <= c.pixels
    for suffix in ["actual", "diff", "side-by-side"]:
        written = tmp_path / f"gallery.{suffix}.png"
        assert written in e.value.written and written.exists(), suffix
    assert numpy.array_equal(softpbr.load_image(tmp_path / "gallery.actual.png"), image)
    # Within a tolerance large enough it passes.
    assert_image_matches(image, golden, max_diff=255, update=False)
    with pytest.raises(ImageMismatch):
        assert_image_matches(image, golden, max_diff=1, max_pixels=10, update=False)


def test_update_mode_rewrites_the_golden(monkeypatch, tmp_path):
    monkeypatch.delenv("SOFTPBR_UPDATE_GOLDENS", raising=False)  # also when the suite runs in update mode
    golden = tmp_path / "new.png"
    image = gradient()
    with pytest.raises(ImageMismatch, match="new.png"):
        assert_image_matches(image, golden)  # missing
    monkeypatch.setenv("SOFTPBR_UPDATE_GOLDENS", "1")
    assert assert_image_matches(image, golden).updated
    monkeypatch.delenv("SOFTPBR_UPDATE_GOLDENS")
    assert_image_matches(image, golden)
    assert numpy.array_equal(softpbr.load_image(golden), image)


def test_the_pytest_option_updates_goldens(tmp_path):
    (tmp_path / "test_one.py").write_text(textwrap.dedent("""
        import numpy
        from softpbr.testing import assert_image_matches
        def test_image():
            assert_image_matches(numpy.full((2, 2, 4), 7, numpy.uint8), "golden.png")
    """))
    env = {k: v for k, v in os.environ.items() if k != "SOFTPBR_UPDATE_GOLDENS"}
    run = lambda *args: subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *args],
                                       cwd=tmp_path, env=env, capture_output=True, text=True)
    failed = run()
    assert failed.returncode == 1 and "golden.png" in failed.stdout, failed.stdout + failed.stderr
    updated = run("--softpbr-update-goldens")
    assert updated.returncode == 0, updated.stdout + updated.stderr
    assert "--softpbr-update-goldens" in run("--help").stdout
    assert (tmp_path / "golden.png").exists()
    assert run().returncode == 0


def test_content_hash_is_the_documented_one():
    assert softpbr.content_hash(numpy.array([[[255, 0, 0, 255]]], numpy.uint8)) == 0xc9fea42538ede09e
