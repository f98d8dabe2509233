"""Drag-update rate of the studio in the browser: a corner of the coat's front panel (about
22K triangles) dragged in headless Chromium; prints the live mesh updates per second seen by
the page, the page's redraw rate and the server's time per update.

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
        box = page.locator(f"#overlay circle[data-key='front/{args['corner']}']").bounding_box()
        x, y = box["x"] + 6, box["y"] + 6
        page.evaluate("studio.dragStats = {frames: 0, ms: 0}")
        page.mouse.move(x, y)
        page.mouse.down()
        t = time.perf_counter()
        k = 0
        while time.perf_counter() - t < a.seconds:
            k += 1
            page.mouse.move(x - 20 * abs(((k / 60) % 2) - 1), y)  # back and forth, 60 steps
            page.wait_for_timeout(4)
        elapsed = time.perf_counter() - t
        frames = page.evaluate("studio.dragStats.frames")
        page.mouse.up()
        browser.close()
    srv.should_exit = True
    print(f"{'garment':<10}{'triangles':>10}{'new [s]':>9}{'coords [s]':>11}"
          f"{'server/update [ms]':>20}{'page updates/s':>16}{'mouse events/s':>16}")
    print(f"{'coat':<10}{mesh.n_triangles:>10}{t_new:>9.1f}{t_coords:>11.2f}"
          f"{1000 * t_server:>20.1f}{frames / elapsed:>16.1f}{k / elapsed:>16.1f}")


if __name__ == "__main__":
    main()
