"""The interactive view in a real browser.

`penedge example 3 --contacts --html` writes the HTML view of the paper's Example 3;
headless Chromium (Debian's packages chromium and chromium-driver, driven by selenium:
`bash scripts/install-browser.sh` installs all three) opens the file from disk, with no
network. The tests check that plotly draws the WebGL scene, that the console shows no
error, that hovering shows block ids and contact types, and that hiding a contact type
from the legend and turning the view work.

Skipped only where Chromium or its driver is not installed.
"""

from __future__ import annotations

import io
import json
import re
import shutil
import time

import numpy as np
import pytest

import penedge

from cli_run import run

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")

pytestmark = pytest.mark.skipif(
    CHROMIUM is None or CHROMEDRIVER is None,
    reason="headless Chromium is not installed (bash scripts/install-browser.sh, or "
    "apt-get install chromium chromium-driver)",
)

DIV = "penedge-view"
READY = f"""
var gd = document.getElementById('{DIV}');
if (!gd || !gd._fullLayout || !gd._fullLayout.scene || !gd._fullLayout.scene._scene) return null;
var canvas = gd.querySelector('.gl-container canvas');
return {{traces: gd._fullData.length, canvas: !!canvas,
         webgl: !!(gd._fullLayout.scene._scene.glplot)}};
"""
WAIT = 120  # seconds: a software-rendered WebGL page on a busy 2-core machine


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    """Example 3's HTML view open in headless Chromium: (driver, path, contacts)."""
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        pytest.skip("selenium is not installed (bash scripts/install-browser.sh installs it)")
    folder = tmp_path_factory.mktemp("browser")
    made = run("example", "3", "--contacts", "--no-picture", "--html-out", "view.html", cwd=folder)
    assert made.returncode == 0, made.stderr
    path = folder / "view.html"
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for argument in (
        "--headless=new",
        "--no-sandbox",
        "--disable-dev-shm-usage",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--window-size=1200,900",
    ):
        options.add_argument(argument)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    # The driver is named, so that selenium looks for nothing on the network.
    driver = webdriver.Chrome(service=Service(executable_path=CHROMEDRIVER), options=options)
    try:
        driver.set_page_load_timeout(WAIT)
        driver.set_script_timeout(WAIT)
        driver.get(path.as_uri())
        state = wait_for(driver, READY)
        assert state is not None, "plotly did not draw the 3D scene"
        yield driver, path, penedge.paper_example(3).detect(geometry=True), state
    finally:
        driver.quit()


def wait_for(driver, script, timeout=WAIT):
    """The first truthy value of `script` (polled), or None after `timeout` seconds."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = driver.execute_script(script)
        if value:
            return value
        time.sleep(0.2)
    return None


def severe(driver):
    """The browser console's errors since the last call."""
    return [entry for entry in driver.get_log("browser") if entry["level"] == "SEVERE"]


def test_the_file_needs_no_network(page):
    _, path, _, _ = page
    text = path.read_text(encoding="utf-8")
    assert not re.search(r"<script[^>]+src=", text)  # plotly.js is inline, no CDN
    assert "Plotly.newPlot" in text


def test_the_scene_renders_without_console_errors(page):
    driver, _, _, state = page
    # 26 blocks (a mesh and its edges each), and one trace per contact type
    assert state == {"traces": 26 * 2 + 3, "canvas": True, "webgl": True}
    assert "WebGL is not supported" not in driver.find_element("tag name", "body").text
    shot = driver.get_screenshot_as_png()
    from matplotlib.image import imread

    pixels = imread(io.BytesIO(shot))[..., :3]
    drawn = (pixels < 0.9).any(axis=-1).mean()  # not white
    assert drawn > 0.1, f"only {drawn:.1%} of the page is drawn"
    colours = len(np.unique((pixels * 255).astype(np.uint8).reshape(-1, 3), axis=0))
    assert colours > 200  # shaded faces of many colours, not a blank canvas
    assert severe(driver) == []


def test_the_legends_name_the_blocks_and_the_contact_types(page):
    driver, _, found, _ = page
    legend = driver.execute_script(
        f"""var gd = document.getElementById('{DIV}');
        return gd._fullData.filter(function (t) {{ return t.showlegend; }})
                           .map(function (t) {{ return [t.legend, t.name]; }});"""
    )
    blocks = [name for where, name in legend if where == "legend"]
    contacts = [name for where, name in legend if where == "legend2"]
    assert blocks == [f"block {i}" for i in range(26)]
    counts = found.counts()
    assert contacts == [f"{name} ({n})" for name, n in counts.items() if n]
    assert contacts == ["vertex-vertex (205)", "edge-edge-superposition (78)", "face-face (42)"]
    assert severe(driver) == []


def hover_sweep(driver, wanted):
    """Moves the mouse over a grid of the canvas; returns every hover event's points as
    (trace name, customdata, label text). Should no event satisfy `wanted`, sweeps again
    with longer pauses (software WebGL on a busy machine can take longer than 0.3 s to
    answer a move)."""
    for pause in (0.3, 1.0, 2.5):
        hovers = _sweep(driver, pause)
        if any(wanted(name) for name, _, _ in hovers):
            break
    return hovers


def _sweep(driver, pause):
    """One sweep of :func:`hover_sweep`, `pause` seconds at each point."""
    from selenium.webdriver.common.action_chains import ActionChains

    driver.execute_script(
        f"""var gd = document.getElementById('{DIV}'); window.penedgeHovers = [];
        gd.removeAllListeners && gd.removeAllListeners('plotly_hover');
        gd.on('plotly_hover', function (e) {{
            var p = e.points[0];
            var labels = Array.from(document.querySelectorAll('g.hovertext'))
                              .map(function (h) {{ return h.textContent; }});
            window.penedgeHovers.push([p.data.name, Array.from(p.customdata), labels]);
        }});"""
    )
    canvas = driver.find_element("css selector", f"#{DIV} .gl-container canvas")
    width, height = canvas.size["width"], canvas.size["height"]
    for fx in (-0.3, -0.15, 0.0, 0.15, 0.3):
        for fy in (-0.3, -0.1, 0.0, 0.1, 0.3):
            ActionChains(driver).move_to_element_with_offset(
                canvas, int(fx * width), int(fy * height)
            ).perform()
            time.sleep(pause)
    time.sleep(0.5)
    return driver.execute_script("return window.penedgeHovers")


def test_hover_shows_the_block_id_and_volume(page):
    driver, _, _, _ = page
    hovers = hover_sweep(driver, lambda name: name.startswith("block "))
    blocks = [(name, data) for name, data, _ in hovers if name.startswith("block ")]
    assert blocks, f"no block under the mouse: {hovers}"
    volumes = penedge.paper_example(3).volumes
    for name, (block, volume, *real) in blocks:
        assert name == f"block {int(block)}"
        assert volume == pytest.approx(volumes[int(block)], rel=1e-6)
        assert all(-1e-6 <= x <= 10 + 1e-6 for x in real)  # where it lies, not exploded
    labels = {label for _, _, shown in hovers for label in shown}
    number = r"[-\u2212]?[\d.]+(?:e[-+\u2212]?\d+)?"  # d3 writes minus as U+2212
    hover = rf"block \d+volume [\d.]+ m³vertex at x {number}, y {number}, z {number} m"
    assert any(re.fullmatch(hover, label) for label in labels), labels
    assert severe(driver) == []


def test_hiding_the_blocks_leaves_the_contacts_to_hover(page):
    driver, _, found, _ = page
    hidden = driver.execute_script(
        f"""var gd = document.getElementById('{DIV}');
        var blocks = [];
        gd._fullData.forEach(function (t, i) {{ if (t.legend === 'legend') blocks.push(i); }});
        return Plotly.restyle(gd, {{visible: 'legendonly'}}, blocks).then(function () {{
            return gd._fullData.filter(function (t) {{ return t.visible === true; }})
                               .map(function (t) {{ return t.legendgroup; }});
        }});"""
    )
    assert set(hidden) == {"vertex-vertex (205)", "edge-edge-superposition (78)", "face-face (42)"}
    hovers = hover_sweep(driver, lambda name: True)
    pairs = {tuple(p) for p in found.pairs.tolist()}
    types = {
        tuple(p): penedge.CONTACT_TYPES[t - 1]
        for p, t in zip(found.pairs.tolist(), found.types, strict=True)
    }
    contacts = [(name, data) for name, data, _ in hovers]
    assert contacts, "no contact under the mouse"
    for name, (a, b) in contacts:
        pair = (int(a), int(b))
        assert pair in pairs
        assert name.startswith(types[pair] + " (")
    labels = {label for _, _, shown in hovers for label in shown}
    assert any(re.fullmatch(r"[a-z-]+blocks \d+ and \d+", label) for label in labels), labels
    driver.execute_script(
        f"var gd = document.getElementById('{DIV}'); return Plotly.restyle(gd, {{visible: true}});"
    )
    assert severe(driver) == []


def test_a_legend_click_hides_a_contact_type(page):
    driver, _, _, _ = page
    item = next(
        element
        for element in driver.find_elements("css selector", ".legend2 .traces")
        if element.text.startswith("face-face")
    )
    item.find_element("css selector", "rect.legend2toggle").click()
    states = wait_for(
        driver,
        f"""var gd = document.getElementById('{DIV}');
        var s = gd._fullData.filter(function (t) {{ return t.legendgroup === 'face-face (42)'; }})
                            .map(function (t) {{ return t.visible; }});
        return s.length && s.every(function (v) {{ return v === 'legendonly'; }}) ? s : null;""",
        timeout=10,
    )
    assert states == ["legendonly"]
    others = driver.execute_script(
        f"""var gd = document.getElementById('{DIV}');
        return gd._fullData.filter(function (t) {{ return t.visible !== true; }}).length;"""
    )
    assert others == 1  # only the face-face polygons are hidden
    assert severe(driver) == []


def test_the_view_turns_and_zooms(page):
    from selenium.webdriver.common.action_chains import ActionChains

    driver, _, _, _ = page
    eye = "return JSON.stringify(document.getElementById('{}')._fullLayout.scene.camera.eye)"
    before = json.loads(driver.execute_script(eye.format(DIV)))
    canvas = driver.find_element("css selector", f"#{DIV} .gl-container canvas")
    ActionChains(driver).move_to_element(canvas).click_and_hold().move_by_offset(
        120, 40
    ).move_by_offset(60, 20).release().perform()
    turned = wait_for(
        driver,
        f"""var e = document.getElementById('{DIV}').layout.scene.camera;
        return e && e.eye ? JSON.stringify(e.eye) : null;""",
        timeout=10,
    )
    assert turned is not None, "dragging did not turn the view"
    assert json.loads(turned) != before
    zoomed = driver.execute_script(
        f"""var gd = document.getElementById('{DIV}');
        return Plotly.relayout(gd, {{'scene.camera.eye': {{x: 0.8, y: -0.8, z: 0.5}}}})
            .then(function () {{ return gd._fullLayout.scene.camera.eye; }});"""
    )
    assert zoomed == {"x": 0.8, "y": -0.8, "z": 0.5}
    assert severe(driver) == []
