"""Drag-update rate of the studio in the browser: a corner of the coat's front panel (about
22K triangles) dragged in headless Chromium; prints the live mesh updates per second seen by
the page, frames per second drawn in the page (the mesh moved by the drag's linear basis between exact
server updates), exact server updates per second, and the page's time per frame.

    python benchmarks/studio.py [--triangles 22000] [--seconds 4]
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import threading
import time


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--triangles", type=int, default=22000)
    ap.add_argument("--seconds", type=float, default=4.0)
    a = ap.parse_args()
    import uvicorn
    from playwright.sync_api import sync_playwright

    from patternfit.studio import create_app
    from patternfit.studio.server import HOST, free_port

    app = create_app(tempfile.mkdtemp())
    studio = app.state.studio
    t = time.perf_counter()
    studio.new(garment="coat", body="male_average", triangles=a.triangles)
    t_new = time.perf_counter() - t
    mesh = studio.session.mesh
    args = {"panel": "front", "corner": mesh.edge_names[1][1], "partner": True}
    t = time.perf_counter()
    studio.drag("move_point", {**args, "offset": [0.001, 0.0]})
    t_coords = time.perf_counter() - t
    n = 30
    t = time.perf_counter()
    for i in range(n):
        studio.drag("move_point", {**args, "offset": [0.001 * i, 0.0]})
    t_server = (time.perf_counter() - t) / n
    port = free_port()
    srv = uvicorn.Server(uvicorn.Config(app, host=HOST, port=port, log_level="warning"))
    threading.Thread(target=srv.run, daemon=True).start()
    while not srv.started:
        time.sleep(0.05)
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=shutil.which("chromium"), args=[
            "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
            "--disable-component-update", "--disable-sync", "--no-first-run",
            "--enable-unsafe-swiftshader"])
        page = browser.new_page(viewport={"width": 1500, "height": 850})
        page.goto(f"http://{HOST}:{port}/")
        page.wait_for_selector("body[data-ready='1']", timeout=60000)
        # pointer moves generated in the page once per animation frame (as a mouse delivers
        # them), back and forth over 20 px: Playwright's own mouse waits for each event's
        # round trip and would measure itself
        page.evaluate("studio.dragStats = {}")
        res = page.evaluate("""async ([key, ms]) => {
            const ed = studio.editor, h = ed.handleList.find((q) => q.key === key);
            ed.drag = { h, x0: 0, y0: 0, offset: [0, 0], moved: true };
            const t0 = performance.now(); let k = 0;
            while (performance.now() - t0 < ms) {
              await new Promise((r) => requestAnimationFrame(r));
              k += 1;
              ed.pointerMove({ clientX: -20 * Math.abs(((k / 60) % 2) - 1), clientY: 0 });
            }
            ed.drag = null;
            return [k, (performance.now() - t0) / 1000];
        }""", [f"front/{args['corner']}", 1000 * a.seconds])
        k, elapsed = res
        st = page.evaluate("studio.dragStats")
        browser.close()
    srv.should_exit = True
    frames = st["frames"]
    print(f"{'garment':<8}{'triangles':>10}{'coords [s]':>11}{'server/exact [ms]':>18}"
          f"{'mouse events/s':>15}{'frames/s':>10}{'exact/s':>9}{'page ms/frame':>14}")
    print(f"{'coat':<8}{mesh.n_triangles:>10}{t_coords:>11.2f}{1000 * t_server:>18.1f}"
          f"{k / elapsed:>15.1f}{1000 * (frames - 1) / (st['t1'] - st['t0']):>10.1f}"
          f"{st.get('exact', 0) / elapsed:>9.1f}{st['drawMs'] / frames:>14.1f}")
    print(f"(mesh of the new session built in {t_new:.1f} s)")


if __name__ == "__main__":
    main()
