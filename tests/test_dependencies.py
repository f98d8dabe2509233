"""Every third-party module the package imports is declared in pyproject.toml (a fresh
machine has only what is declared: an undeclared import passes here only by luck)."""

from __future__ import annotations

import ast
import re
import sys
import tomllib
from importlib.metadata import packages_distributions
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _declared() -> set[str]:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    reqs = list(project["dependencies"])
    for extra in project.get("optional-dependencies", {}).values():
        reqs += extra
    return {re.split(r"[<>=!~\[ ;]", r, maxsplit=1)[0].lower().replace("_", "-") for r in reqs}


def _imported() -> set[str]:
    names = set()
    for path in (ROOT / "src" / "patternfit").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                names |= {a.name.split(".")[0] for a in node.names}
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names.add(node.module.split(".")[0])
    return names - set(sys.stdlib_module_names) - {"patternfit"}


def test_every_imported_module_is_declared():
    dists = packages_distributions()
    declared = _declared()
    missing = {}
    for module in sorted(_imported()):
        owners = {d.lower().replace("_", "-") for d in dists.get(module, [module])}
        if not owners & declared:
            missing[module] = sorted(owners)
    assert not missing, f"imported but not declared in pyproject.toml: {missing}"


def test_trimesh_hole_filling_has_its_graph_library():
    # trimesh.repair.fill_holes imports networkx lazily; it is declared for that reason
    assert "networkx" in _declared()
    import networkx  # noqa: F401
