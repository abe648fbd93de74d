"""ctest python_installed: the package that `cmake --install` put in the folder argv[1] imports
from there, has its metadata and pytest entry point, and renders. Not a pytest module."""

import importlib.metadata
import sys
from pathlib import Path

import softpbr

folder = Path(sys.argv[1]).resolve()
assert Path(softpbr.__file__).resolve().is_relative_to(folder), f"imported {softpbr.__file__}, not from {folder}"
assert importlib.metadata.version("softpbr") == softpbr.__version__
plugins = [e.value for e in importlib.metadata.entry_points(group="pytest11") if e.name == "softpbr"]
assert plugins == ["softpbr.pytest_plugin"], plugins
image = softpbr.render({"objects": [{"mesh": {"type": "cube"}}], "lights": [{"type": "point", "position": [1, 2, 3]}],
                        "render": {"width": 32, "height": 24}})
assert image.shape == (24, 32, 4) and image[..., :3].max() > 0
print(f"softpbr {softpbr.__version__} from {folder}: imports, entry point, render ok")
