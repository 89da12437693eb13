"""Real-browser check of ``gridfield explore MAP --web`` (not part of the pytest suite).

Starts ``gridfield explore maps/seed000.yaml --web`` on 127.0.0.1, loads the page in a headless
chromium driven by playwright, clicks a start and a goal on the canvas, checks that the server
planned a path between them and that the path's red line appears in the browser's picture where it
should (and was not there before), then draws a triangular robot, computes its C-space and saves
a screenshot of the browser view to ``docs/figures/explorer_web.png``.

Needs ``pip install playwright`` (the ``browser-check`` extra) and a chromium binary; it never
downloads browsers. Usage::

    python tools/check_web_explorer.py [--chromium /usr/bin/chromium] [--screenshot docs/figures/explorer_web.png]

Exit code 0 when every check passed, 1 otherwise (the failed check is printed).
"""

from __future__ import annotations

import argparse
import io
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))  # tools/, also when this file is not run as a script
from webagg_explorer import ExplorerServer, button_pixel, data_pixel, free_port  # tools/webagg_explorer.py

REPO = Path(__file__).resolve().parents[1]
MAP = REPO / "maps" / "seed000.yaml"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--no-first-run"]
START, GOAL = (2.0, 2.0), (20.0, 3.0)
PROBE = ((9.0, 1.0), (13.0, 3.5))  # a box the new path crosses and the initial one does not
RED = (214, 39, 40)  # tab:red, the path's colour


def layout() -> dict[str, object]:
    """Canvas pixel positions (y down) of map points and buttons, from an identical figure."""
    os.environ.setdefault("MPLBACKEND", "Agg")
    sys.path.insert(0, str(REPO))
    import matplotlib

    matplotlib.use("Agg")
    from gridfield.explore import Explorer
    from gridfield.io import read_world

    ex = Explorer(read_world(MAP))
    ex.figure.canvas.draw()

    def data(x: float, y: float) -> tuple[float, float]:
        return data_pixel(ex, x, y)

    out = {"data": data, "draw_robot": button_pixel(ex, "toggle_robot_drawing"),
           "cspace": button_pixel(ex, "compute_cspace"), "toggle_3d": button_pixel(ex, "toggle_3d"),
           "size": ex.figure.canvas.get_width_height()}
    out["probe"] = (data(PROBE[0][0], PROBE[1][1]), data(PROBE[1][0], PROBE[0][1]))  # top-left, bottom-right
    return out


def red_pixels(png: bytes, box: tuple[tuple[float, float], tuple[float, float]]) -> int:
    import numpy as np
    from PIL import Image

    img = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
    (x0, y0), (x1, y1) = box
    win = img[int(y0):int(y1), int(x0):int(x1)]
    return int((np.abs(win - np.array(RED)).sum(axis=2) < 60).sum())


def changed_fraction(a: bytes, b: bytes) -> float:
    import numpy as np
    from PIL import Image

    x = np.asarray(Image.open(io.BytesIO(a)).convert("RGB")).astype(int)
    y = np.asarray(Image.open(io.BytesIO(b)).convert("RGB")).astype(int)
    return float((np.abs(x - y).sum(axis=2) > 30).mean())


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--chromium", default="/usr/bin/chromium")
    ap.add_argument("--screenshot", default=str(REPO / "docs" / "figures" / "explorer_web.png"))
    args = ap.parse_args()
    from playwright.sync_api import sync_playwright

    geo = layout()
    port = free_port()
    server = ExplorerServer([str(MAP), "--web", "--port", str(port)], timeout=90.0, echo=True)
    try:
        url = server.wait_for(r"gridfield explorer: (http://127\.0\.0\.1:\d+/)").group(1)
        print(f"page: {url}")
        with sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=args.chromium, args=CHROMIUM_ARGS, headless=True)
            w, h = geo["size"]  # type: ignore[misc]
            page = browser.new_page(viewport={"width": w + 60, "height": h + 120}, device_scale_factor=1)
            page.goto(url)
            canvas = page.locator("canvas.mpl-canvas").first
            canvas.wait_for(state="visible", timeout=30000)
            page.wait_for_timeout(3000)  # the first image
            box = canvas.bounding_box()
            assert box is not None, "no canvas on the page"
            print(f"canvas at ({box['x']:.0f}, {box['y']:.0f}), {box['width']:.0f} x {box['height']:.0f} px")
            ox, oy = box["x"], box["y"]

            def click(xy: tuple[float, float], button: str = "left") -> None:
                page.mouse.click(ox + xy[0], oy + xy[1], button=button)  # type: ignore[arg-type]

            def shot() -> bytes:
                return canvas.screenshot()

            data = geo["data"]
            before = red_pixels(shot(), geo["probe"])  # type: ignore[arg-type]
            click(data(*START))  # type: ignore[operator]
            m = server.wait_for(r"start set to \(([-\d.e]+), ([-\d.e]+)\)")
            assert abs(float(m.group(1)) - START[0]) < 0.1 and abs(float(m.group(2)) - START[1]) < 0.1, m.group(0)
            server.wait_for(r"potential: ")
            click(data(*GOAL))  # type: ignore[operator]
            m = server.wait_for(r"goal set to \(([-\d.e]+), ([-\d.e]+)\)")
            assert abs(float(m.group(1)) - GOAL[0]) < 0.1 and abs(float(m.group(2)) - GOAL[1]) < 0.1, m.group(0)
            status = server.wait_for(r"potential: (\w+), (\d+) steps")
            assert status.group(1) == "reached", status.group(0)
            page.wait_for_timeout(2500)
            after = red_pixels(shot(), geo["probe"])  # type: ignore[arg-type]
            print(f"red path pixels in the probe box: {before} before the clicks, {after} after")
            assert before == 0 and after > 20, "the path did not appear in the browser"
            # the seed 004 workflow: draw a triangular robot (first vertex = reference point), C-space
            click(geo["draw_robot"])  # type: ignore[arg-type]
            server.wait_for(r"drawing the robot")
            for v in [(2.0, 1.2), (3.0, 1.2), (2.0, 2.4)]:
                click(data(*v))  # type: ignore[operator]
                page.wait_for_timeout(300)
            click(data(2.3, 1.6), button="right")  # type: ignore[operator]
            server.wait_for(r"potential: ")
            click(geo["cspace"])  # type: ignore[arg-type]
            status = server.wait_for(r"potential: (\w+).*robot polygon")
            page.wait_for_timeout(3000)
            Path(args.screenshot).parent.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=args.screenshot)
            print(f"C-space planned ({status.group(1)}); wrote {args.screenshot}")
            # the 3-D toggle replaces the map by the potential surface in the browser too
            flat = shot()
            click(geo["toggle_3d"])  # type: ignore[arg-type]
            page.wait_for_timeout(4000)
            changed = changed_fraction(flat, shot())
            print(f"3-D view: {changed:.0%} of the canvas changed")
            assert changed > 0.2, "the 3-D toggle did not change the browser's picture"
            browser.close()
    except AssertionError as e:
        print(f"FAILED: {e}")
        return 1
    finally:
        server.stop()
    print("OK: the browser drove the web explorer to a drawn path")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
