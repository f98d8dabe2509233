"""``patternfit studio`` on a port it cannot have: refused before anything is announced,
opened or created."""

from __future__ import annotations

import socket

from typer.testing import CliRunner

from patternfit.cli.main import app
from patternfit.studio import server


def test_a_busy_port_is_refused_before_anything_happens(tmp_path, monkeypatch):
    opened = []
    monkeypatch.setattr(server.webbrowser, "open", opened.append)
    with socket.socket() as other:  # another studio listening on the port
        other.bind((server.HOST, 0))
        other.listen()
        port = other.getsockname()[1]
        r = CliRunner().invoke(app, ["studio", "--port", str(port),
                                     "--session", str(tmp_path / "s")])
    assert r.exit_code == 2, r.output
    assert f"--port {port}: already in use (another studio?)" in r.output
    assert "--port 0 for a free one" in r.output
    assert "patternfit studio on" not in r.output  # no address of another studio announced
    assert "Traceback" not in r.output and "Errno" not in r.output
    assert not (tmp_path / "s").exists() and not opened


def test_port_0_is_a_free_one():
    with server.bind(0) as a, server.bind(None) as b:
        assert a.getsockname()[1] > 0 and b.getsockname()[1] > 0
    r = CliRunner().invoke(app, ["studio", "--port", "-1"])
    assert r.exit_code == 2 and "0..65535" in r.output
