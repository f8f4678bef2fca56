"""Browser test of the sphere's 3-D contact patch in the Interface tab (issue 25), through Debian's chromium.

Run alone with ``python -m pytest -m browser tests/app/test_browser_patch.py`` (Playwright, no browser
download, ``/usr/bin/chromium``). One server for the module (the real library, warmed up as in
:mod:`test_browser`, whose page helpers this reuses). The test opens the Interface tab, chooses the
sphere, and reads from BokehJS what the patch figures and the fretting loop draw: their titles, legend
entries, the finite cells of each patch image, colour bar titles (the units) and the loop's points.
"""

import math
import time

import pytest
from test_browser import Page, start_server, stop_server, until

pytestmark = pytest.mark.browser

#: what an image plot titled ``prefix...`` draws: its finite cells and its colour bar's title
IMAGE_JS = """
(prefix) => {
  const stack = Object.values(Bokeh.index), seen = new Set();
  while (stack.length) {
    const v = stack.pop();
    if (!v || seen.has(v)) continue;
    seen.add(v);
    const m = v.model;
    if (m && m.title && typeof m.title.text === "string" && m.title.text.startsWith(prefix) && v.frame) {
      const images = (m.renderers ?? []).filter(r => r.glyph && r.glyph.type === "Image");
      const cells = images.map(r => Array.from(r.data_source.data.image[0] ?? []).filter(Number.isFinite));
      const bars = [...(m.right ?? []), ...(m.below ?? [])].filter(c => c.color_mapper);
      return {title: m.title.text, finite: cells.map(c => c.length), values: cells.flat(),
              bars: bars.map(b => b.title)};
    }
    if (typeof v.children === "function") for (const c of v.children()) stack.push(c);
  }
  return null;
}
"""
SPHERE = "sphere (3-D), partial slip"


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    log_path = tmp_path_factory.mktemp("server") / "panel.log"
    proc, url = start_server(log_path)
    yield url
    stop_server(proc, log_path)


def test_the_sphere_shows_its_patch_from_above_and_its_fretting_loop(browser, server):
    """Feature (issue 25): the Interface tab shows the sphere's patch seen from above (pressure, shear,
    stick/slip/open map with a legend entry per state, worn depth; colour bars with units) and the fretting
    loop at the first and last records."""
    page = Page(browser, server, width=1500)
    try:
        page.tab("Interface")
        page.wait_title("Interface: FRF of pad_x")  # the cylinder first: no patch on the page
        assert not any(t.startswith("Interface: 3-D patch") for t in page.titles())
        start = time.perf_counter()
        page.page.locator(".bk-btn", has_text=SPHERE).click()
        page.wait_title("Interface: 3-D patch, worn depth at N = 1e+05")
        page.idle()
        patches = {
            "pressure": "pressure p, cycle mean (MPa)",
            "shear": "shear traction |q|, cycle peak (MPa)",
            "stick / slip / open": "over the cycle",
            "worn depth": "worn depth w (µm)",
        }
        for what, unit in patches.items():
            prefix = f"Interface: 3-D patch, {what} at N = 1e+05"
            # the figures are drawn one after the other: an image's data may follow its title by a moment
            image = until(
                lambda p=prefix: (i := page.page.evaluate(IMAGE_JS, p)) and sum(i["finite"]) and i or None
            )
            # the 29 pairs mirrored, the 9 on the symmetry plane once
            assert image["finite"] == [49] and image["bars"] == [unit], what
            labels = [item["label"] for item in page.plot(prefix)["legends"]]
            circles = ["Hertz radius a", "Mindlin stick radius c"]
            states = ["sticks (never slips)", "slips", "open all cycle"]
            assert labels == (states + circles if what.startswith("stick") else circles), what
        codes = set(page.page.evaluate(IMAGE_JS, "Interface: 3-D patch, stick")["values"])
        assert codes == {0, 1, 2}  # partial slip: a stick disk, a slip annulus, open around
        wear = page.page.evaluate(IMAGE_JS, "Interface: 3-D patch, worn depth")["values"]
        assert max(wear) > 0 and min(wear) == 0  # the stick disk unworn
        loop = until(
            lambda: (lg := page.plot("Interface: fretting loop")["legends"]) and lg[0]["n"] and lg or None
        )
        assert [f["label"] for f in loop] == ["N = 0", "N = 1e+05"] and loop[0]["n"] == loop[1]["n"] > 0
        assert all(math.isfinite(v) for f in loop for v in f["x"] + f["y"])
        assert max(loop[0]["y"]) > 0 > min(loop[0]["y"])  # the force turns with the holder
        seconds = time.perf_counter() - start
        print(f"sphere chosen to its patch and loop drawn: {seconds:.1f} s")
        page.check_clean()
    finally:
        page.context.close()
