"""The .pyi stubs editors read describe the compiled module: every class, method, attribute
and function they declare exists, and every public name of the module is declared."""

from __future__ import annotations

import ast
from pathlib import Path

import softpbr
from softpbr import _softpbr


def test_the_stubs_match_the_module():
    tree = ast.parse((Path(softpbr.__file__).parent / "_softpbr.pyi").read_text())
    missing = []
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            cls = getattr(_softpbr, node.name, None)
            if cls is None:
                missing.append(node.name)
                continue
            for item in node.body:
                name = item.name if isinstance(item, ast.FunctionDef) else \
                    item.target.id if isinstance(item, ast.AnnAssign) else None
                if name and not hasattr(cls, name):
                    missing.append(f"{node.name}.{name}")
        elif isinstance(node, ast.FunctionDef) and not hasattr(_softpbr, node.name):
            missing.append(node.name)
    assert missing == [], "declared in _softpbr.pyi, missing from the module"
    declared = {n.name for n in tree.body if isinstance(n, (ast.ClassDef, ast.FunctionDef))}
    undeclared = [n for n in dir(_softpbr) if not n.startswith("_") and n not in declared]
    assert undeclared == [], "public in the module, missing from _softpbr.pyi"
    assert all(hasattr(softpbr, n) for n in softpbr.__all__)
