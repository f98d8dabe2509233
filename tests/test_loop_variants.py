"""The variants of the paper's Figs 15–17 (``patternfit reproduce variants``): a variant
whose drape fails its checks says so in its row and on its picture; it showed a coloured ϖ
map, and its JSON row no reason."""

from pathlib import Path

import pytest
from typer.testing import CliRunner

from patternfit.cli.main import app
from patternfit.fit.report import failure
from patternfit.loop import table2


def test_a_failed_variant_names_its_reasons_and_its_picture_says_failed(tmp_path,
                                                                         monkeypatch):
    drawn = {}
    monkeypatch.setattr(table2, "plot_3d_map",
                        lambda *a, failed=None, **k: drawn.update(failed=failed))
    monkeypatch.setattr(table2, "compress_png", lambda *a: None)
    # an XL skirt half as wide again falls off the thin body
    row = table2.run_variant(("x", "skirt", "female_thin", "huge", "XL", (1.5, 1.0)),
                             triangles=600, figures=tmp_path)
    assert row["checks_passed"] is False and row["reasons"]
    assert drawn["failed"] == failure({"passed": False, "reasons": row["reasons"]})
    assert "below the waist" in drawn["failed"]


def test_the_paper_commands_do_not_write_into_the_documentation(tmp_path, monkeypatch):
    """--figures defaulted to docs/figures: run in a checkout, it overwrote the tracked
    pictures; a file given as the folder is refused before any drape."""
    import inspect

    from patternfit.cli import loop

    for command in (loop.table2, loop.variants):
        assert inspect.signature(command).parameters["figures"].default.default == \
            Path("reproduce")
    monkeypatch.chdir(tmp_path)
    (tmp_path / "f").write_text("a file")
    monkeypatch.setattr(table2, "run_variant", lambda *a, **k: pytest.fail("drape started"))
    result = CliRunner().invoke(app, ["reproduce", "variants", "--figures", "f"])
    assert result.exit_code == 2 and "is a file" in result.output
