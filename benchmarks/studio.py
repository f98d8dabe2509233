"""The studio at the 22K coat in headless Chromium: page load of a draped session, live drag
rate, release of a drag to the applied edit; this tree against an older commit.

    python benchmarks/studio.py [--triangles 22000] [--seconds 4] [--old 75ecbe1] [--repeat 3]
                                [--session /tmp/studio-coat22k]

Prints one table, a row per tree (``--old REF``: the package of that commit, extracted with
``git archive`` into a temporary folder, measured by this same script in a subprocess). The
draped session is made once (by the oldest tree, whose files every later one reads) and
each measurement starts from a copy of it; with ``--repeat N`` the trees take turns N times
(each row in a process of its own) and the table gives each figure's median, so that a
machine whose load changes meets both alike. ``--session DIR`` keeps the draped session in
``DIR`` (made on the first run, a 22K drape takes minutes): later runs start from it.

- load [s]: page opened until ready (options, state, geometry, garment and body drawn),
  median of 3 loads of the draped session; MB: bytes of /api/geometry, /api/garment3d
  and /api/body as the page fetches them.
- exact/s: exact previews from the server per second while a corner of the front is
  dragged (pointer moves generated in the page once per animation frame, as a mouse
  delivers them); frames/s and ms/frame: the page's live mesh redraws and its work per
  redraw.
- release [s]: pointer released until the edit is applied and the page shows it, median of
  3 drags (each drag first runs 1.5 s).

Issue 22's targets: load <= 1 s, exact >= 15/s, ms/frame <= 4, release <= 0.5 s.
"""

from __future__ import annotations

import argparse
import io
import json
import os
import shutil
import statistics
import subprocess
import sys
import tarfile
import tempfile
import threading
import time
from pathlib import Path

ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--disable-sync", "--no-first-run",
        "--enable-unsafe-swiftshader"]

# drag the handle ``key`` for ``ms``: a pointer move each animation frame, back and forth
# over 20 px; returns [moves, seconds]
DRAG = """async ([key, ms]) => {
    const ed = studio.editor, h = ed.handleList.find((q) => q.key === key);
    ed.drag = { h, x0: 0, y0: 0, offset: [0, 0], moved: true, accepted: [0, 0] };
    const t0 = performance.now(); let k = 0;
    while (performance.now() - t0 < ms) {
      await new Promise((r) => requestAnimationFrame(r));
      k += 1;
      ed.pointerMove({ clientX: -20 * Math.abs(((k / 60) % 2) - 1), clientY: 0 });
    }
    return [k, (performance.now() - t0) / 1000];
}"""

# release the drag at 12 px left; seconds until the page shows the applied edit
RELEASE = """async () => {
    const ed = studio.editor, p0 = studio.state.position;
    ed.pointerMove({ clientX: -12, clientY: 0 });
    const t0 = performance.now();
    ed.pointerUp({ clientX: -12, clientY: 0 });
    while (!(studio.state && studio.state.position === p0 + 1))
      await new Promise((r) => setTimeout(r, 2));
    return (performance.now() - t0) / 1000;
}"""

# bytes of the page's three big fetches, as the page asks for them
SIZES = """async () => {
    let n = 0;
    for (const e of performance.getEntriesByType("resource"))
      if (/api\\/(geometry|garment3d|body)/.test(e.name)) n += e.encodedBodySize;
    return n;
}"""


def prepare(folder: str, triangles: int) -> None:
    """A studio session in ``folder``: the coat on male_average, draped (made beside it
    and renamed when done, so that an interrupted run leaves no half-made session)."""
    from patternfit.studio.state import Studio

    part = Path(f"{folder}.part")
    shutil.rmtree(part, ignore_errors=True)
    studio = Studio(part)
    studio.new(garment="coat", body="male_average", triangles=triangles)
    studio.start_drape()
    studio.wait()
    if studio.session.positions is None:
        raise SystemExit(f"the drape failed: {studio.job.error}")
    studio.flush()
    part.rename(folder)


def measure(session: str, seconds: float) -> dict:
    """One tree's row (the ``patternfit`` on ``sys.path``), on a copy of the draped
    ``session`` folder."""
    import uvicorn
    from playwright.sync_api import sync_playwright

    from patternfit.studio import create_app
    from patternfit.studio.server import HOST, free_port

    folder = Path(tempfile.mkdtemp()) / "studio"
    shutil.copytree(session, folder)
    app = create_app(folder)
    studio = app.state.studio
    mesh = studio.session.mesh
    corner = mesh.edge_names[1][1]
    key = f"front/{corner}"
    studio.drag("move_point", {"panel": "front", "corner": corner, "partner": True,
                               "offset": [0.001, 0.0]})  # the coordinates: not measured
    port = free_port()
    srv = uvicorn.Server(uvicorn.Config(app, host=HOST, port=port, log_level="warning"))
    threading.Thread(target=srv.run, daemon=True).start()
    while not srv.started:
        time.sleep(0.05)
    row = {"triangles": mesh.n_triangles}
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=shutil.which("chromium"), args=ARGS)
        page = browser.new_page(viewport={"width": 1500, "height": 850})
        loads = []
        for _ in range(3):
            t = time.perf_counter()
            page.goto(f"http://{HOST}:{port}/")
            page.wait_for_selector("body[data-ready='1']", timeout=120000)
            loads.append(time.perf_counter() - t)
        row["load"] = statistics.median(loads)
        row["mb"] = page.evaluate(SIZES) / 1e6
        page.evaluate("studio.dragStats = {}")
        k, elapsed = page.evaluate(DRAG, [key, 1000 * seconds])
        st = page.evaluate("studio.dragStats")
        row["moves"] = k / elapsed
        row["frames"] = 1000 * (st["frames"] - 1) / (st["t1"] - st["t0"])
        row["exact"] = st.get("exact", 0) / elapsed
        row["ms_frame"] = st["drawMs"] / st["frames"]
        releases = [page.evaluate(RELEASE)]
        for _ in range(2):
            page.evaluate(DRAG, [key, 1500])
            releases.append(page.evaluate(RELEASE))
        row["release"] = statistics.median(releases)
        browser.close()
    srv.should_exit = True
    return row


def extract(ref: str, into: str) -> str:
    """The ``src`` folder of commit ``ref``, extracted under ``into``."""
    root = Path(__file__).resolve().parent.parent
    archive = subprocess.run(["git", "-C", str(root), "archive", ref, "src"],
                             check=True, capture_output=True).stdout
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(into, filter="data")
    return str(Path(into) / "src")


def run(src: str | None, *args: str) -> str:
    """This script run in a process of its own over ``src`` (None: this tree's)."""
    env = dict(os.environ) if src is None else {**os.environ, "PYTHONPATH": src}
    return subprocess.run([sys.executable, __file__, *args], env=env, check=True,
                          capture_output=True, text=True).stdout


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--triangles", type=int, default=22000)
    ap.add_argument("--seconds", type=float, default=4.0)
    ap.add_argument("--old", default=None, help="a commit to compare with (e.g. 75ecbe1)")
    ap.add_argument("--repeat", type=int, default=1, help="turns of each tree (medians)")
    ap.add_argument("--session", default=None,
                    help="a folder for the draped session, made once and reused")
    ap.add_argument("--row", default=None, help=argparse.SUPPRESS)  # a session to measure
    ap.add_argument("--prepare", default=None, help=argparse.SUPPRESS)  # a folder to fill
    a = ap.parse_args()
    if a.prepare:
        prepare(a.prepare, a.triangles)
        return
    if a.row:  # one tree's measurement, as JSON
        print(json.dumps(measure(a.row, a.seconds)))
        return
    with tempfile.TemporaryDirectory() as tmp:
        trees = [(a.old, extract(a.old, tmp))] if a.old else []
        trees.append(("this tree", None))
        session = a.session or str(Path(tmp) / "session")
        if not Path(session).exists():
            run(trees[0][1], "--prepare", session, "--triangles", str(a.triangles))
        runs = {name: [] for name, _ in trees}
        for _ in range(a.repeat):
            for name, src in trees:
                out = run(src, "--row", session, "--seconds", str(a.seconds))
                runs[name].append(json.loads(out.strip().splitlines()[-1]))
    rows = [(name, {k: statistics.median(r[k] for r in rs) for k in rs[0]})
            for name, rs in runs.items()]
    print(f"{'tree':<10}{'triangles':>10}{'load [s]':>10}{'MB':>7}{'moves/s':>9}"
          f"{'frames/s':>10}{'exact/s':>9}{'ms/frame':>10}{'release [s]':>13}")
    for name, r in rows:
        print(f"{name:<10}{int(r['triangles']):>10}{r['load']:>10.2f}{r['mb']:>7.2f}"
              f"{r['moves']:>9.1f}{r['frames']:>10.1f}{r['exact']:>9.1f}{r['ms_frame']:>10.2f}"
              f"{r['release']:>13.2f}")
    print(f"medians of {a.repeat} turn(s) each; targets (issue 22): load <= 1 s, exact >= 15/s, "
          "ms/frame <= 4, release <= 0.5 s")


if __name__ == "__main__":
    main()
