"""The package's shape (docs/architecture.md): stages import only downwards, no sub-package
takes another's private names, and the front ends run the pipeline through the API."""

from __future__ import annotations

import ast
import importlib
import re
from collections import defaultdict
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "patternfit"

#: the stages, lowest first; a module imports only from its own sub-package or lower ranks
RANK = {"constants": 0, "errors": 0, "files": 0, "geometry": 0, "arguments": 0, "defaults": 0,
        "text": 0,
        "figures": 0,
        "pattern": 1, "body": 1, "coords": 1, "mesh": 2, "sim": 3, "fit": 4, "edit": 5,
        "loop": 6, "api": 7, "cli": 8, "studio": 8, "batch": 8}
#: the pipeline's steps: a front end calls them through patternfit.api, never directly
PIPELINE = {"mesh_pattern", "drape", "drape_with", "redrape", "FitEvaluator", "evaluate_fit",
            "write_fit_outputs", "write_correction_outputs", "load_any_pattern",
            "load_body_mesh", "load_fabric", "get_fabric", "place_on_body",
            "place_on_cylinders"}
FRONT_ENDS = {"cli", "studio", "batch"}


def _imports():
    """(importing sub-package, file, imported sub-package, imported module path, names)."""
    out = []
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC)
        package = rel.parts[0].removesuffix(".py")
        if package == "__init__":
            continue
        here = ["patternfit", *rel.with_suffix("").parts]
        if here[-1] == "__init__":
            here = here[:-1]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    # a package's __init__ is the package itself: one level less to go up
                    base = here[:len(here) - node.level + (rel.name == "__init__.py")]
                    full = base + (node.module.split(".") if node.module else [])
                elif node.module and node.module.split(".")[0] == "patternfit":
                    full = node.module.split(".")
                else:
                    continue
                names = [a.name for a in node.names]
                if len(full) == 1:  # from patternfit import edit, api
                    for name in names:
                        out.append((package, rel, name, ["patternfit", name], []))
                else:
                    out.append((package, rel, full[1], full, names))
            elif isinstance(node, ast.Import):
                for a in node.names:
                    parts = a.name.split(".")
                    if parts[0] == "patternfit" and len(parts) > 1:
                        out.append((package, rel, parts[1], parts, []))
    return out


IMPORTS = _imports()


def test_every_sub_package_has_a_rank():
    packages = {p.name.removesuffix(".py") for p in SRC.iterdir()
                if p.name != "__init__.py" and (p.suffix == ".py" or (p / "__init__.py").exists())}
    assert packages <= set(RANK), packages - set(RANK)


def test_no_import_runs_back_up_the_stages():
    up = [f"{rel}: {'.'.join(full)}" for pkg, rel, tgt, full, _ in IMPORTS
          if tgt != pkg and RANK.get(tgt, -1) > RANK[pkg]]
    assert not up, "\n".join(up)


def test_no_circle_between_sub_packages():
    graph = defaultdict(set)
    for pkg, _, tgt, _, _ in IMPORTS:
        if tgt != pkg:
            graph[pkg].add(tgt)

    def reach(start):
        seen, todo = set(), [start]
        while todo:
            for nxt in graph[todo.pop()]:
                if nxt not in seen:
                    seen.add(nxt)
                    todo.append(nxt)
        return seen

    circles = [p for p in list(graph) if p in reach(p)]
    assert not circles, circles


def test_no_sub_package_takes_another_ones_private_names():
    private = [f"{rel}: {'.'.join(full)} {n}" for pkg, rel, tgt, full, names in IMPORTS
               if tgt != pkg for n in names if n.startswith("_")]
    private += [f"{rel}: {'.'.join(full)}" for pkg, rel, tgt, full, _ in IMPORTS
                if tgt != pkg and any(p.startswith("_") for p in full[2:])]
    assert not private, "\n".join(private)


def test_no_command_module_imports_another():
    cross = [f"{rel}: {'.'.join(full)}" for pkg, rel, _, full, _ in IMPORTS
             if pkg == "cli" and rel.name not in ("main.py", "__init__.py")
             and full[:2] == ["patternfit", "cli"]
             and full[-1] not in ("app", "show")]
    assert not cross, "\n".join(cross)


@pytest.mark.parametrize("front", sorted(FRONT_ENDS))
def test_front_ends_run_the_pipeline_through_the_api(front):
    direct = [f"{rel}: {'.'.join(full)} {n}" for pkg, rel, tgt, full, names in IMPORTS
              if pkg == front and tgt not in ("api", pkg) for n in names if n in PIPELINE]
    assert not direct, "\n".join(direct)


def test_the_package_re_exports_every_api_name():
    """README: the names of patternfit.api are re-exported from patternfit; eight of them
    (suggest_seams, write_pattern, ...) were not."""
    import patternfit
    import patternfit.api

    assert sorted(patternfit.__all__) == sorted(["__version__", *patternfit.api.__all__])
    assert all(getattr(patternfit, n) is getattr(patternfit.api, n)
               for n in patternfit.api.__all__)


def _named_in_docs() -> list[tuple[str, int, str, str]]:
    """(file, line, kind, name) of what README.md and docs/*.md point at: links to local
    files ("link") and dotted names of patternfit's code in backticks ("name"), these of
    three parts at least or starting with ``patternfit.`` (two-part ones are mostly an
    object's attribute, ``body.distance_field``)."""
    root = SRC.parents[1]
    packages = {p.stem for p in SRC.iterdir() if not p.name.startswith("_")}
    out = []
    for f in [root / "README.md", *sorted((root / "docs").glob("*.md"))]:
        text = f.read_text(encoding="utf-8")
        line = lambda m: text.count("\n", 0, m.start()) + 1  # noqa: E731
        for m in re.finditer(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text):
            if not m.group(1).startswith(("http:", "https:", "mailto:")):
                out.append((f, line(m), "link", m.group(1)))
        for m in re.finditer(r"`([A-Za-z_][\w.]*)(?:\([^`]*\))?`", text):
            parts = m.group(1).split(".")
            if parts[0] == "patternfit" or (len(parts) >= 3 and parts[0] in packages
                                            and not parts[-1].isdigit()):
                out.append((f, line(m), "name", m.group(1)))
    return out


def _resolves(name: str) -> bool:
    parts = name.split(".")
    parts = parts if parts[0] == "patternfit" else ["patternfit", *parts]
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ImportError:
            continue
        for attr in parts[k:]:
            if not hasattr(obj, attr):
                return False
            obj = getattr(obj, attr)
        return True
    return False


def test_the_docs_name_what_exists():
    """Every local link of the README and docs resolves, and every dotted name of the code
    they give exists: docs/simulation.md named ``mesh.store.saved_at_rest`` long after its
    rename, and the README linked METHOD.md outside the repository."""
    root = SRC.parents[1].resolve()
    missing = [f"{f.name}:{n}: {kind} {name}" for f, n, kind, name in _named_in_docs()
               if (kind == "link" and not ((f.parent / name).exists()
                                           and (f.parent / name).resolve().is_relative_to(root)))
               or (kind == "name" and not name.endswith(FILE_ENDINGS) and not _resolves(name))]
    assert not missing, "\n".join(missing)


#: the endings of file names, which the docs write in backticks as code names are
FILE_ENDINGS = (".py", ".json", ".npz", ".npy", ".md", ".png", ".csv", ".dxf", ".txt", ".glb",
                ".obj", ".ply", ".svg", ".pdf", ".html", ".toml", ".cpp")
