"""The softpbr pytest plugin: ``--softpbr-update-goldens`` turns on update mode for
softpbr.testing.assert_image_matches (as SOFTPBR_UPDATE_GOLDENS=1 does).

Loaded automatically when softpbr is on the path (the package's pytest11 entry point);
otherwise add ``-p softpbr.pytest_plugin`` or ``pytest_plugins = ["softpbr.pytest_plugin"]``.
"""

from __future__ import annotations

from typing import Any

from . import testing


def pytest_addoption(parser: Any) -> None:
    group = parser.getgroup("softpbr")
    group.addoption("--softpbr-update-goldens", action="store_true", default=False,
                    help="rewrite golden images that are missing or differ instead of failing "
                         "(softpbr.testing.assert_image_matches; also SOFTPBR_UPDATE_GOLDENS=1)")


def pytest_configure(config: Any) -> None:
    testing.update_goldens = bool(config.getoption("softpbr_update_goldens", default=False))


def pytest_report_header(config: Any) -> str:
    return "softpbr goldens: " + ("update mode (goldens are rewritten)" if testing.update_mode() else "checked")
