"""The README's scripting example runs as written, using only the public API."""

from __future__ import annotations

import ast
import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def _example() -> str:
    text = README.read_text(encoding="utf-8")
    section = text.split("## Scripting: the public API", 1)[1]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_the_example_imports_only_the_top_level_package():
    tree = ast.parse(_example())
    imported = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    imported |= {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    assert imported == {"patternfit"}


def test_the_readme_example_drapes_evaluates_and_edits(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    exec(compile(_example(), str(README), "exec"), {"__name__": "readme_example"})
    report = tmp_path / "skirt-fit" / "report.json"
    assert report.is_file() and (tmp_path / "skirt-fit" / "fit_3d.png").is_file()
