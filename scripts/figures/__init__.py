"""The figures a reader looks at, drawn from the CSVs alone (out/wp_<scene>.csv, out/wp_orders.csv,
out/stability_map.csv) and a small description of each scene and method passed in:

  style.py      method -> family (one table), colour, marker; FMI 3.0 = hollow marker
  data.py       reading the CSVs tolerantly; Pareto front, best runs, second-reference test
  describe.py   SceneInfo from a scene object of the caller's (duck-typed)
  legible.py    label placement and the legibility check (matplotlib bounding boxes); palette PNG
  wp.py         one scene's work-precision + convergence figure
  stability.py  the stability map figure
  report.py     out/report.html (plotly, JavaScript embedded, offline)
  browser.py    headless Chromium over the DevTools pipe (the report's test)
  publish.py    everything at once, also into docs/img/
  __main__.py   `.venv/bin/python scripts/figures --from out [--docs docs/img]`

Uses matplotlib, numpy, Pillow and plotly; nothing here imports scripts/cosim except __main__
(which builds the descriptions from it when run as a program).
"""
from .data import SceneInfo  # noqa: F401
from .describe import scene_info  # noqa: F401
from .publish import publish  # noqa: F401
