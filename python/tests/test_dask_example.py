"""examples/dask_thumbnails.py on a dask.distributed LocalCluster of 2 workers: a folder of
models to thumbnails, a task that fails once retried, a bad model reported without stopping
the others, and every thumbnail the bits the command writes. Skipped without Dask (Debian:
python3-distributed)."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
import threading
from pathlib import Path

import numpy
import pytest

import softpbr

distributed = pytest.importorskip("dask.distributed")


@pytest.fixture(scope="module")
def example():
    source = Path(__file__).resolve().parents[2] / "examples" / "dask_thumbnails.py"
    spec = importlib.util.spec_from_file_location("dask_thumbnails", source)
    module = importlib.util.module_from_spec(spec)
    sys.modules["dask_thumbnails"] = module  # importable by name: tasks refer to its functions
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def client():
    # Workers in this process (threads): the tasks are this module's functions, and
    # softpbr.render releases the GIL, so the two workers render at once.
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def models_folder(tmp_path: Path, source_dir: Path) -> Path:
    folder = tmp_path / "models"
    folder.mkdir()
    subprocess.run([sys.executable, str(source_dir / "cli" / "tests" / "make_diff_models.py")], cwd=folder, check=True)
    for name in ("cube_copy.gltf", "cube_moved.gltf"):
        (folder / name).unlink()
    (folder / "broken.glb").write_bytes((folder / "cube.glb").read_bytes()[:300])
    return folder


# Attempts per model, counted by flaky() in the workers (threads of this process). Tasks are
# pickled by reference to this module's functions, so the state is this module's.
attempts = {}
lock = threading.Lock()


def flaky(model, output, size):
    """The example's task, except that cube_back.gltf fails on its first attempt (as a task
    on a worker lost mid-way would)."""
    with lock:
        attempts[model] = attempts.get(model, 0) + 1
        first = attempts[model] == 1
    if first and model.endswith("cube_back.gltf"):
        raise OSError("transient failure")
    return sys.modules["dask_thumbnails"].render_thumbnail(model, output, size)


def test_a_folder_of_models_on_two_workers_with_a_retry(tmp_path, source_dir, example, client, cli):
    folder = models_folder(tmp_path, source_dir)
    attempts.clear()

    models = sorted(folder.iterdir())
    models = [m for m in models if m.suffix in (".glb", ".gltf")]
    results = example.thumbnails(client, models, tmp_path / "thumbs", size=64, retries=2, task=flaky)
    back = str(folder / "cube_back.gltf")
    broken = str(folder / "broken.glb")
    assert attempts[back] == 2 and results[back].endswith("cube_back.png")
    assert results[broken].startswith("error: ") and "broken.glb" in results[broken]
    assert attempts[broken] == 3  # the first try and its 2 retries
    written = [m for m in models if not results[str(m)].startswith("error")]
    assert len(written) == 3
    # The same bits as the command, model by model.
    for model in written:
        ours = softpbr.load_image(results[str(model)])
        theirs = tmp_path / "cli.png"
        subprocess.run([cli, "render", str(model), "-o", str(theirs), "--width", "64", "--height", "64", "-q"], check=True)
        assert numpy.array_equal(ours, softpbr.load_image(theirs)), model
    # The cluster the tasks ran on: two workers.
    assert len(client.scheduler_info()["workers"]) == 2
