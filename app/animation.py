"""The animation of one period, played by the browser: its frames and the player that shows them.

The server draws the cycle scene's figures at one instant; while the animation
plays, the browser moves them itself (:class:`Player`): every frame's data is
sent once per solution (:func:`browser_frames`), and at each of the browser's
own frames the player writes one into the Bokeh models it finds by name (set by
:func:`named` on the live figures). A frame then costs the browser a few data
writes and the server nothing, so that the period plays smoothly at any load;
paused, the player hands its frame to the server, which draws the same instant.
"""

from __future__ import annotations

from typing import Any

import holoviews as hv
import param
from panel.custom import JSComponent

from fretwear.figures.sketch import LAYERS

#: prefix of the names of the models the player writes into
PREFIX = "fw-anim-"
#: the sketch's layers that move (the walls stand still)
MOVING = tuple(name for name in LAYERS if name != "walls")
#: digits kept of the drawing's coordinates (drawing units of about 10: far below a pixel)
DIGITS = 4


def named(element: hv.Element | hv.Overlay, **handles: str) -> Any:
    """``element`` whose Bokeh models are named ``PREFIX + name`` when drawn, for each ``handle=name``
    (``source``, ``glyph``, or ``title``: the plot's title): the player's way to find them."""

    def hook(plot: Any, _element: Any) -> None:
        for handle, name in handles.items():
            model = plot.handles["plot"].title if handle == "title" else plot.handles[handle]
            model.name = PREFIX + name

    return element.opts(hooks=[hook], backend="bokeh")


def _columns(kind: str, layer: list) -> dict[str, list]:
    """The columns of the Bokeh data source HoloViews draws a sketch ``layer`` of ``kind`` with."""

    def r(values: Any) -> list:
        return [round(float(v), DIGITS) for v in values]

    if kind in ("rectangles", "segments"):
        names = ("left", "bottom", "right", "top") if kind == "rectangles" else ("x0", "y0", "x1", "y1")
        return {name: r(row[i] for row in layer) for i, name in enumerate(names)}
    if kind == "points":
        return {"x": r(p[0] for p in layer), "y": r(p[1] for p in layer)}
    if kind == "path":
        return {"xs": [r(xs) for xs, _ in layer], "ys": [r(ys) for _, ys in layer]}
    if kind == "polygons":  # one ring per polygon, closed
        return {f"{axis}s": [[[r([*p[axis], p[axis][0]])]] for p in layer] for axis in ("x", "y")}
    return {"x": r(t[0] for t in layer), "y": r(t[1] for t in layer), "text": [t[2] for t in layer]}


def browser_frames(animation: dict | None) -> dict:
    """The player's data from :meth:`CycleScene.animation`: per frame, the cursors' positions, the
    sketch's title and interface colour, and the columns of each moving layer's data source (keyed by
    the names :func:`named` gives the models). Empty without a solution."""
    if animation is None:
        return {}
    sources: dict[str, dict[str, list]] = {}
    for frame in animation["layers"]:
        for name in MOVING:
            columns = sources.setdefault(PREFIX + f"sketch-{name}", {})
            for column, values in _columns(LAYERS[name], frame[name]).items():
                columns.setdefault(column, []).append(values)
    sources[PREFIX + "cursor-loop"] = {"x": [[x] for x in animation["loop_x"]],
                                      "y": [[y] for y in animation["loop_y"]]}  # fmt: skip
    return {
        "frames": len(animation["t"]),
        "t": animation["t"],
        "title": animation["title"],
        "color": animation["color"],
        "sources": sources,
    }


class Player(JSComponent):
    """Plays :func:`browser_frames` in the browser: ``period`` seconds per period while ``playing``; the
    frame shown when paused goes to ``frame`` (the server then draws that instant), a ``frame`` set by
    the server (the instant slider) is where the next play starts. ``fps``: the frames shown per second,
    as the browser measured them over the last second of play."""

    data = param.Dict(default={}, doc="The frames (browser_frames)")
    playing = param.Boolean(False, doc="Whether the animation plays")
    period = param.Number(4.0, bounds=(1.0, 30.0), doc="Seconds per period of the response")
    frame = param.Integer(0, bounds=(0, None), doc="Frame shown (set by the browser on pause)")
    fps = param.Number(0.0, doc="Frames shown per second, measured by the browser")

    _esm = f"""
    const PREFIX = "{PREFIX}";
    export function render({{ model }}) {{
      let found = {{}}, shown = -1, start = null, count = 0, since = 0, running = false;
      // the named models of the figures on screen, found by one walk of the page's views (a figure drawn
      // anew for a new window width leaves its old copy in the document: writing it would cost a draw)
      function collect() {{
        found = {{}};
        const stack = window.Bokeh ? Object.values(window.Bokeh.index) : [], seen = new Set();
        while (stack.length) {{
          const v = stack.pop();
          if (!v || seen.has(v)) continue;
          seen.add(v);
          const m = v.model;
          if (m && m.title && v.frame && v.canvas_view.el.getBoundingClientRect().width > 0)
            for (const r of [m.title, ...(m.center ?? []), ...(m.renderers ?? [])])
              for (const x of [r, r.data_source, r.glyph])
                if (x && typeof x.name === "string" && x.name.startsWith(PREFIX))
                  (found[x.name] ??= []).push(x);
          if (typeof v.children === "function") for (const c of v.children()) stack.push(c);
        }}
      }}
      // (walked again each second of play, on new frames and when a figure is removed)
      function get(name) {{
        let models = found[name] ?? [];
        if (models.some(m => m.document == null)) {{ collect(); models = found[name] ?? []; }}
        return models;
      }}
      // not sent back: the server keeps the instant it drew
      function set(models, values) {{ for (const m of models) m.setv(values, {{sync: false}}); }}
      function show(k) {{
        const d = model.data;
        for (const [name, columns] of Object.entries(d.sources)) {{
          for (const source of get(name)) {{
            const data = Object.assign({{}}, source.data);
            for (const [column, frames] of Object.entries(columns)) data[column] = frames[k];
            set([source], {{data}});
          }}
        }}
        for (const name of ["cursor-displacements", "cursor-force"])
          set(get(PREFIX + name), {{location: d.t[k]}});
        set(get(PREFIX + "sketch-title"), {{text: d.title[k]}});
        set(get(PREFIX + "sketch-color"), {{line_color: d.color[k]}});
        shown = k;
        count += 1;
      }}
      function tick(now) {{
        const d = model.data;
        if (!model.playing || !d.frames) {{ running = false; return; }}
        const period = 1000 * model.period;
        if (start === null) start = now - period * (Math.max(shown, model.frame, 0) / d.frames);
        const k = Math.floor((((now - start) / period) % 1) * d.frames);
        if (k !== shown) show(k);
        if (now - since >= 1000) {{
          model.fps = count * 1000 / (now - since);
          count = 0;
          since = now;
          collect();  // figures drawn anew since (a new window width, a new solution) have new models
        }}
        requestAnimationFrame(tick);
      }}
      function play() {{
        if (running || !model.playing) return;
        running = true; start = null; count = 0; since = performance.now(); shown = -1;
        collect();
        requestAnimationFrame(tick);
      }}
      model.on("playing", () => {{
        if (model.playing) play();
        else if (shown >= 0) model.frame = shown;  // the server draws the same instant
      }});
      model.on("period", () => {{ start = null; }});  // the phase shown carries on at the new speed
      // new frames (a new solution, or the first ones after Play was pressed before they came)
      model.on("data", () => {{ start = null; collect(); play(); }});
      play();
      return document.createElement("span");
    }}
    """
