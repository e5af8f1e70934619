"""out/report.html: one self-contained page (plotly.js embedded, no request leaves it) with, at
the top, per scene the best method at H = 1 ms and 10 ms, within a CPU budget and the cheapest
for an error target (the last two recomputed in the page when the budget or target is changed);
then every scene's work-precision and convergence chart (one plotly figure each, a method's
traces grouped so that clicking its legend entry hides it everywhere; hovering a point gives
method, FMI version, H, error, CPU and FMI calls), and the stability map.

Uses plotly (Python) and this package (data, style); reads only the CSVs given.
"""
from __future__ import annotations

import html
import json
import math

import plotly.graph_objects as go
from plotly.offline import get_plotlyjs
from plotly.subplots import make_subplots

from . import data
from .style import PLOTLY_SYMBOL, Styles, fmi_version, fmt_h, split

FRONT = "rgba(255,198,26,0.45)"
CONFIG = {"displaylogo": False, "responsive": True, "toImageButtonOptions": {"format": "png"}}


def _hover(r, column="error"):
    return [r.method, fmi_version(r.method), fmt_h(r.H), f"{r.cpu:.3g}", r.fmi_calls,
            f"{r.value(column):.3g}" if r.ok(column) else r.why_not]


HOVER = ("<b>%{customdata[0]}</b> (FMI %{customdata[1]})<br>H = %{customdata[2]}<br>"
         "error = %{customdata[5]}<br>CPU = %{customdata[3]} s<br>FMI calls = %{customdata[4]}<extra></extra>")


def _symbol(styles, method):
    base, version = split(method)
    sym = PLOTLY_SYMBOL.get(styles.look(base).marker, "circle")
    return sym + ("-open" if version == 3 else "")


def scene_figure(info: data.SceneInfo, runs, styles: Styles, orders=None):
    """The plotly figure of one scene: work-precision, convergence, and the informative further
    references; a method's traces share its legend group."""
    columns = [("error", "convergence: error against H")]
    columns += [(c, "convergence, error " + lab.replace("\n", " ")[:60]) for c, lab in info.second
                if data.tells_more(runs, c)[0]]
    fig = make_subplots(rows=1, cols=1 + len(columns), horizontal_spacing=0.07,
                        subplot_titles=["work-precision: error against CPU time"] + [t for _, t in columns])
    front = data.pareto(runs)
    if front:
        fig.add_trace(go.Scatter(x=[r.cpu for r in front], y=[r.value() for r in front], mode="lines",
                                 line=dict(color=FRONT, width=12), name="Pareto front (cheapest for its error)",
                                 legendgroup="front", hoverinfo="skip"), row=1, col=1)
    order = {b: i for i, b in enumerate(styles.bases())}
    methods = sorted(data.methods(runs), key=lambda m: (order.get(split(m)[0], 99), split(m)[1]))
    tops = {}
    for j, (column, _) in enumerate(columns, start=2):
        vals = [r.value(column) for r in runs if r.ok(column)]
        tops[column] = max(vals) * 4 if vals else 1.0
    for k, method in enumerate(methods):
        look = styles.look(method)
        hollow = split(method)[1] == 3
        o = (orders or {}).get((info.name, method), (None,))[0]
        name = method.replace("@fmi3", " (FMI 3.0)") + (f" · order {o:.2f}" if o is not None else "")
        rs = sorted((r for r in runs if r.method == method), key=lambda r: -r.H)
        marker = dict(symbol=_symbol(styles, method), color=look.color, size=10 if hollow else 7,
                      line=dict(color=look.color, width=1.5))
        line = dict(color=look.color, width=1.6, dash="dash" if look.ls == "--" else "solid")
        mode = "markers" if hollow else "lines+markers"
        ok = [r for r in rs if r.ok()]
        fig.add_trace(go.Scatter(x=[r.cpu for r in ok], y=[r.value() for r in ok], mode=mode, name=name,
                                 legendgroup=method, marker=marker, line=line,
                                 customdata=[_hover(r) for r in ok], hovertemplate=HOVER), row=1, col=1)
        for j, (column, _) in enumerate(columns, start=2):
            ok = [r for r in rs if r.ok(column)]
            fig.add_trace(go.Scatter(x=[r.H for r in ok], y=[r.value(column) for r in ok], mode=mode,
                                     name=name, legendgroup=method, showlegend=False, marker=marker,
                                     line=line, customdata=[_hover(r, column) for r in ok],
                                     hovertemplate=HOVER), row=1, col=j)
            bad = [r for r in rs if not r.ok(column)]
            if bad:
                fig.add_trace(go.Scatter(
                    x=[r.H for r in bad], y=[tops[column] * 1.5 ** (k % 8)] * len(bad), mode="markers",
                    name=name + ": no result", legendgroup=method, showlegend=False,
                    marker=dict(symbol="x-thin-open", size=9, color=look.color, line=dict(width=2, color=look.color)),
                    customdata=[_hover(r, column) for r in bad],
                    hovertemplate=HOVER.replace("error = ", "no result: ")), row=1, col=j)
    for j, (column, _) in enumerate(columns, start=2):
        pts = [r for r in runs if r.ok(column)]
        if pts:
            h_hi = max(r.H for r in runs)
            lo, hi = min(r.value(column) for r in pts), max(r.value(column) for r in pts)
            y0 = min(hi, lo * 100)
            for p, dash in ((1, "dash"), (2, "dot")):
                fig.add_trace(go.Scatter(x=[h_hi, h_hi / 10], y=[y0, y0 / 10 ** p], mode="lines",
                                         name=f"slope {p}", legendgroup=f"slope{p}", showlegend=j == 2,
                                         line=dict(color="#555", dash=dash, width=1.3), hoverinfo="skip"),
                              row=1, col=j)
        fig.update_xaxes(type="log", autorange="reversed", title_text="macro step H [s] (finer →)",
                         exponentformat="power", row=1, col=j)
        fig.update_yaxes(type="log", title_text="relative error", exponentformat="power", row=1, col=j)
    fig.update_xaxes(type="log", title_text="CPU time of the run [s]", row=1, col=1)
    fig.update_yaxes(type="log", title_text="relative error", exponentformat="power", row=1, col=1)
    fig.update_layout(height=470, margin=dict(l=60, r=20, t=40, b=50), template="plotly_white",
                      legend=dict(font=dict(size=11), groupclick="togglegroup"),
                      hoverlabel=dict(font_size=12))
    fig.update_annotations(font_size=12)
    return fig


def stability_figure(stab: data.Stability, styles: Styles, labels=None):
    fig = make_subplots(rows=1, cols=2, horizontal_spacing=0.08, subplot_titles=[
        "largest stable ωH against ζ (markers measured, lines closed form)",
        "ζ = 0: spectral radius of the one-step map"])
    methods = list(dict.fromkeys(r["method"] for r in stab.limits + stab.rhos))
    order = {b: i for i, b in enumerate(styles.bases())}
    for method in sorted(methods, key=lambda m: order.get(m, 99)):
        look = styles.look(method)
        sym = PLOTLY_SYMBOL.get(look.marker, "circle")
        name = (labels or {}).get(method, method)
        rs = sorted((r for r in stab.limits if r["method"] == method), key=lambda r: r["zeta"])
        hov = "<b>" + html.escape(method) + "</b><br>%{customdata}<extra></extra>"
        fig.add_trace(go.Scatter(x=[r["zeta"] for r in rs], y=[max(r["measured"], 1e-4) for r in rs],
                                 mode="markers", name=name, legendgroup=method,
                                 marker=dict(symbol=sym, color=look.color, size=8),
                                 customdata=[f"ζ = {r['zeta']:g}: largest stable ωH {r['measured']:.4g} "
                                             f"(closed form {r['closed_form']:.4g})" for r in rs],
                                 hovertemplate=hov), row=1, col=1)
        fig.add_trace(go.Scatter(x=[r["zeta"] for r in rs], y=[max(r["closed_form"], 1e-4) for r in rs],
                                 mode="lines", legendgroup=method, showlegend=False, hoverinfo="skip",
                                 line=dict(color=look.color, width=1.2)), row=1, col=1)
        rh = sorted((r for r in stab.rhos if r["method"] == method), key=lambda r: r["omegaH"])
        fin = [r for r in rh if math.isfinite(r["measured"])]
        fig.add_trace(go.Scatter(x=[r["omegaH"] for r in fin], y=[r["measured"] for r in fin], mode="markers",
                                 legendgroup=method, showlegend=False, marker=dict(symbol=sym, color=look.color, size=7),
                                 customdata=[f"ωH = {r['omegaH']:.3g}: ρ = {r['measured']:.6g} (closed form "
                                             f"{r['closed_form']:.6g})" for r in fin],
                                 hovertemplate=hov), row=1, col=2)
        inf = [r for r in rh if not math.isfinite(r["measured"])]
        if inf:
            fig.add_trace(go.Scatter(x=[r["omegaH"] for r in inf], y=[40.0] * len(inf), mode="markers",
                                     legendgroup=method, showlegend=False,
                                     marker=dict(symbol="x-thin-open", size=9, color=look.color,
                                                 line=dict(width=2, color=look.color)),
                                     customdata=[f"ωH = {r['omegaH']:.3g}: did not converge" for r in inf],
                                     hovertemplate=hov), row=1, col=2)
        fig.add_trace(go.Scatter(x=[r["omegaH"] for r in rh], y=[r["closed_form"] if math.isfinite(r["closed_form"])
                                                                else None for r in rh],
                                 mode="lines", legendgroup=method, showlegend=False, hoverinfo="skip",
                                 line=dict(color=look.color, width=1.1)), row=1, col=2)
    fig.update_xaxes(title_text="damping ratio ζ", row=1, col=1)
    fig.update_yaxes(type="log", title_text="largest stable ωH (1e-4: never stable)", row=1, col=1)
    fig.update_xaxes(type="log", title_text="ωH", row=1, col=2)
    fig.update_yaxes(type="log", range=[-1.3, 1.8], title_text="spectral radius (× at 40: did not converge)",
                     row=1, col=2)
    fig.update_layout(height=470, margin=dict(l=60, r=20, t=40, b=50), template="plotly_white",
                      legend=dict(font=dict(size=11)))
    fig.update_annotations(font_size=12)
    return fig


def _cell(r, t_end=None):
    if r is None:
        return "<td class=none>no result</td>"
    return (f"<td><b>{html.escape(split(r.method)[0])}</b> (FMI {fmi_version(r.method)})<br>"
            f"<span>H {fmt_h(r.H)}, error {r.value():.1e}, CPU {r.cpu:.3g} s</span></td>")


def summary(infos, runs_of, budget, target):
    """The rows of the table at the top: (scene, best at 1 ms, at 10 ms, within the budget, cheapest
    for the target), the last two per simulated second of the scene's t_end (1 s where unknown)."""
    rows = []
    for name, runs in runs_of.items():
        t_end = infos[name].t_end or 1.0
        rows.append((name, data.best_at(runs, 1e-3), data.best_at(runs, 1e-2),
                     data.best_within(runs, budget * t_end), data.cheapest_for(runs, target)))
    return rows


JS = """
function fmtH(H){return H>=1e-4*0.999? (+(H*1e3).toPrecision(3))+' ms' : (+(H*1e6).toPrecision(3))+' µs';}
function cell(r){ if(!r) return '<td class=none>no result</td>';
  return '<td><b>'+r.m.split('@')[0]+'</b> (FMI '+(r.m.endsWith('@fmi3')?'3.0':'2.0')+')<br><span>H '+fmtH(r.H)+
    ', error '+r.e.toExponential(1)+', CPU '+(+r.c.toPrecision(3))+' s</span></td>';}
function best(runs, keep, key){ let b=null; for(const r of runs){ if(keep(r) && (!b || key(r,b))) b=r;} return b; }
function recompute(){
  const budget=parseFloat(document.getElementById('budget').value), target=parseFloat(document.getElementById('target').value);
  for(const [name, s] of Object.entries(RUNS)){
    const row=document.getElementById('row-'+name);
    const w=best(s.runs, r=>r.c<=budget*s.t_end, (r,b)=>r.e<b.e||(r.e==b.e&&r.c<b.c));
    const t=best(s.runs, r=>r.e<=target, (r,b)=>r.c<b.c||(r.c==b.c&&r.e<b.e));
    row.cells[3].outerHTML=cell(w); row.cells[4].outerHTML=cell(t);
  }
}
"""


def page(infos, runs_of, styles, orders, stab=None, budget=0.1, target=1e-3, commit="", labels=None):
    """The report's HTML text."""
    charts = [(f"chart-{name}", infos[name].title or name, scene_figure(infos[name], runs, styles, orders))
              for name, runs in runs_of.items()]
    if stab is not None:
        charts.append(("chart-stability", "§7 stability map", stability_figure(stab, styles, labels)))
    rows = summary(infos, runs_of, budget, target)
    table = "".join(f"<tr id='row-{n}'><th>{html.escape(infos[n].title or n)}</th>{_cell(a)}{_cell(b)}"
                    f"{_cell(c)}{_cell(d)}</tr>" for n, a, b, c, d in rows)
    runs_js = {n: {"t_end": infos[n].t_end or 1.0,
                   "runs": [{"m": r.method, "H": r.H, "e": r.value(), "c": r.cpu} for r in runs
                            if r.ok() and math.isfinite(r.cpu)]} for n, runs in runs_of.items()}
    sections = "".join(
        f"<section><h2>{html.escape(title)}</h2>"
        + (f"<p class=err>error: {html.escape(infos[cid[6:]].error_label)}</p>" if cid[6:] in infos else "")
        + f"<div class=chart id='{cid}' data-chart='{cid[6:]}'></div></section>" for cid, title, _ in charts)
    figs = "{" + ",".join(f"{json.dumps(cid)}: {fig.to_json()}" for cid, _, fig in charts) + "}"
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; script-src 'unsafe-inline' 'unsafe-eval'; style-src 'unsafe-inline'; img-src data: blob:; font-src data:">
<title>Co-simulation coupling methods: accuracy against cost</title>
<style>
body {{ font-family: sans-serif; margin: 1.2em auto; padding: 0 1em; max-width: 1500px; color: #222; }}
table {{ border-collapse: collapse; font-size: 13px; }} td, th {{ border: 1px solid #ccc; padding: 4px 8px; text-align: left; vertical-align: top; }}
td span {{ color: #555; font-size: 12px; }} td.none {{ color: #a33; }} .err {{ color: #555; font-size: 13px; margin: 0; }}
h2 {{ font-size: 17px; margin: 1.4em 0 0.2em; }} .chart {{ width: 100%; min-height: 470px; }} input {{ width: 6em; }}
</style></head><body>
<h1>Co-simulation coupling methods: accuracy against cost</h1>
<p>From the CSVs of <code>./scripts/charts</code>{(' at commit <code>' + html.escape(commit) + '</code>') if commit else ''}.
Lower left is better: the yellow band is the Pareto front (no run is both cheaper and more accurate).
Hover a point for method, FMI version, H, error, CPU and FMI calls; click a legend entry to hide
a method, double-click to show it alone. × marks a run without a result at its H.</p>
<p><label>CPU budget <input id=budget type=number step=any value="{budget:g}"> s of CPU per simulated second</label>
&nbsp; <label>error target <input id=target type=number step=any value="{target:g}"></label></p>
<table id=best><tr><th>scene</th><th>best at H = 1 ms</th><th>best at H = 10 ms</th>
<th>best within the CPU budget</th><th>cheapest for the error target</th></tr>{table}</table>
{sections}
<script>{get_plotlyjs()}</script>
<script>
const CONFIG = {json.dumps(CONFIG)};
const RUNS = {json.dumps(runs_js)};
{JS}
document.getElementById('budget').addEventListener('change', recompute);
document.getElementById('target').addEventListener('change', recompute);
const FIGS = {figs};
Promise.all(Object.entries(FIGS).map(([id, f]) => Plotly.newPlot(id, f.data, f.layout, CONFIG)))
  .then(() => {{ document.body.dataset.chartsDrawn = String(Object.keys(FIGS).length); }});
</script></body></html>
"""


def write(path, infos, out, styles=None, budget=0.1, target=1e-3, commit="", labels=None):
    """Read the CSVs in `out` and write the report to `path`; returns the number of charts."""
    csvs = data.scene_csvs(out)
    names = [n for n in infos if n in csvs] + [n for n in csvs if n not in infos]   # the caller's order
    runs_of = {n: data.read_runs(csvs[n]) for n in names}
    infos = {n: infos.get(n) or data.SceneInfo(name=n, title=n) for n in runs_of}
    styles = styles or Styles({m for rs in runs_of.values() for m in data.methods(rs)})
    stab_csv = out / "stability_map.csv"
    stab = data.read_stability(stab_csv) if stab_csv.is_file() else None
    text = page(infos, runs_of, styles, data.read_orders(out / "wp_orders.csv"), stab, budget, target,
                commit, labels)
    path.write_text(text, encoding="utf-8")
    return len(runs_of) + (stab is not None)
