#!/usr/bin/env python3
"""Thumbnails of a folder of models on a Dask cluster (Debian: python3-distributed).

    python3 examples/dask_thumbnails.py MODELS/ THUMBS/ [--size 256] [--scheduler tcp://host:8786]

Each model (.glb, .gltf) is one task: softpbr.render releases the GIL, so a worker's
threads render at once, and the image is the bits `softpbr render model.glb -o x.png
--width S --height S` writes, on any machine. A task that fails is retried (a worker lost,
a file still being copied); a model that keeps failing is reported with its error, and the
others are written. Without --scheduler a LocalCluster of 2 workers runs on this machine;
with it the same code runs on a real cluster (every worker needs softpbr and the files).
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import Callable, Dict, List

import softpbr


def render_thumbnail(model: str, output: str, size: int) -> str:
    """One task: the model's thumbnail, written atomically (write_png); returns the output."""
    softpbr.write_png(output, softpbr.render(model, width=size, height=size))
    return output


def thumbnails(client, models: List[Path], out_dir: Path, size: int = 256, retries: int = 2,
               task: Callable[[str, str, int], str] = render_thumbnail) -> Dict[str, str]:
    """Renders every model to out_dir/<name>.png on the client's cluster, each task retried
    up to `retries` times. Returns {model: output path, or "error: ..."}."""
    from dask.distributed import as_completed

    out_dir.mkdir(parents=True, exist_ok=True)
    futures = {}
    for model in models:
        output = str(out_dir / (model.stem + ".png"))
        # pure=False: a task reruns even with the same arguments (a retried or resubmitted model).
        futures[client.submit(task, str(model), output, size, retries=retries, pure=False)] = str(model)
    results: Dict[str, str] = {}
    for future in as_completed(futures):
        model = futures[future]
        try:
            results[model] = future.result()
        except Exception as e:  # the task's own error, after its retries
            results[model] = f"error: {e}"
    return results


def main(argv: List[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("models", type=Path)
    parser.add_argument("thumbs", type=Path)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--scheduler", help="a Dask scheduler's address; default: a LocalCluster of 2 workers")
    args = parser.parse_args(argv)
    from dask.distributed import Client, LocalCluster

    models = sorted(p for p in args.models.iterdir() if p.suffix.lower() in (".glb", ".gltf"))
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        client = Client(LocalCluster(n_workers=2, threads_per_worker=max(1, (os.cpu_count() or 2) // 2)))
    with client:
        results = thumbnails(client, models, args.thumbs, args.size)
    failed = {m: r for m, r in results.items() if r.startswith("error: ")}
    for model, error in sorted(failed.items()):
        print(f"{model}: {error[len('error: '):]}", file=sys.stderr)
    print(f"{len(results)} models: {len(results) - len(failed)} written to {args.thumbs}, {len(failed)} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
