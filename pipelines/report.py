#!/usr/bin/env python3
"""The run report of a pipelines/character.mk build: OUT/report/index.html, one self-contained
page (no network) with every stage's figures, the PNG previews and a three.js viewer playing
character.glb's sequences and previews/animation.glb.

  report.py OUT [--name character] [--three NODE_MODULES_PARENT] [--output FILE]

--three names the folder holding node_modules/three (scripts/vendor_three.sh installs it); its
ES modules are inlined through an import map of data: URLs. Without it the page has no viewer.
"""
import argparse
import base64
import html
import json
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import summary  # noqa: E402  (the same figures as the text summary)

VIEWER_MODULES = {"three": "build/three.module.js",
                  "three/addons/loaders/GLTFLoader.js": "examples/jsm/loaders/GLTFLoader.js",
                  "three/addons/controls/OrbitControls.js": "examples/jsm/controls/OrbitControls.js",
                  "three/addons/libs/meshopt_decoder.module.js": "examples/jsm/libs/meshopt_decoder.module.js"}
IMPORT = re.compile(r"""((?:\bfrom|\bimport)\s*)(['"])([^'"]+)\2""")


def esc(text):
    return html.escape(str(text))


def number(value, digits=2):
    return "–" if value is None or (isinstance(value, float) and math.isnan(value)) else f"{value:.{digits}f}"


def table(header, rows):
    head = "".join(f"<th>{esc(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{esc(c)}</td>" for c in row) + "</tr>" for row in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def line_plot(series, y_label, x_label="frame (tree order)", width=900, height=260):
    """Inline SVG of named series of (x, y) points sharing one axis."""
    points = [p for _, values, _ in series for p in values]
    if not points:
        return "<p>no data</p>"
    x_max = max(x for x, _ in points) or 1
    y_max = max(y for _, y in points) or 1
    left, bottom = 60, 30
    sx = lambda x: left + (width - left - 10) * x / x_max  # noqa: E731
    sy = lambda y: height - bottom - (height - bottom - 10) * y / y_max  # noqa: E731
    parts = [f'<svg width="{width}" height="{height}" role="img" aria-label="{esc(y_label)}">',
             f'<line x1="{left}" y1="{height - bottom}" x2="{width - 10}" y2="{height - bottom}" stroke="#333"/>',
             f'<line x1="{left}" y1="10" x2="{left}" y2="{height - bottom}" stroke="#333"/>']
    for k in range(5):
        y = y_max * k / 4
        parts.append(f'<text x="{left - 6}" y="{sy(y) + 4:.1f}" text-anchor="end" font-size="11">{y:.3g}</text>')
    parts.append(f'<text x="{left}" y="{height - 8}" font-size="11">{esc(x_label)} 0 … {x_max}</text>')
    parts.append(f'<text x="{left + 6}" y="20" font-size="12">{esc(y_label)}</text>')
    for index, (name, values, colour) in enumerate(series):
        path = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in values)
        parts.append(f'<polyline fill="none" stroke="{colour}" stroke-width="1.5" points="{path}"/>')
        parts.append(f'<text x="{width - 200}" y="{24 + 16 * index}" font-size="12" fill="{colour}">{esc(name)}</text>')
    parts.append("</svg>")
    return "".join(parts)


def alignment_section(out):
    alignment = summary.load(out, "aligned/report/alignment.json")
    tree = summary.load(out, "aligned/report/similarity.json")
    parts = ["<h2>Alignment</h2>"]
    if tree and "quality" in tree:
        parts.append(f"<p>Similarity tree: {esc(tree.get('frames'))} frames, root {esc(tree.get('root'))}, quality ratio "
                     f"{number(tree['quality'].get('ratio'), 3)} (true deformation along the tree / optimal).</p>")
    if not alignment:
        parts.append("<p>No alignment report (the later stages read another database).</p>")
        return "".join(parts)
    frames = alignment.get("frames", [])
    mean = [(i, 1000 * f.get("mean_residual_m", 0)) for i, f in enumerate(frames)]
    worst = [(i, 1000 * f.get("max_residual_m", 0)) for i, f in enumerate(frames)]
    parts.append(line_plot([("mean residual (mm)", mean, "#1f5fbf"), ("max residual (mm)", worst, "#d9782d")],
                           "alignment residual per frame, mm"))
    truth = alignment.get("ground_truth")
    if truth:
        parts.append(f"<p>Against the ground truth: RMS {number(truth.get('rms_percent_height'))} % of the height, "
                     f"worst frame {esc(truth.get('worst_frame'))} {number(truth.get('worst_frame_rms_percent_height'))} %.</p>")
        depth = [(d["depth"], d["rms_percent_height"]) for d in truth.get("by_depth", [])]
        if depth:
            parts.append(line_plot([("RMS % of height", depth, "#2d9d4f")], "ground-truth RMS by tree depth, % of height",
                                  "depth in the similarity tree"))
    return "".join(parts)


def models_section(out):
    parts = ["<h2>Part models</h2>"]
    learn = summary.load(out, "parts/report/learn.json")
    if learn:
        rows = [(name, p.get("kept"), number(p.get("energy"), 4) if isinstance(p.get("energy"), float) else p.get("energy"))
                for name, p in sorted(learn.get("parts", {}).items())]
        parts.append(table(["part", "basis vectors kept", "energy kept"], rows))
    else:
        parts.append("<p>No part models.</p>")
    spaces, transitions = [], []
    report_dir = os.path.join(out, "motion", "report")
    for file in sorted(os.listdir(report_dir)) if os.path.isdir(report_dir) else []:
        report = summary.load(out, os.path.join("motion", "report", file)) or {}
        for name, s in sorted(report.get("spaces", {}).items()):
            v = s.get("validation", {})
            spaces.append((name, s.get("references"), number(v.get("hybrid_max_error_mm")),
                           number(v.get("linear_max_error_mm")), s.get("tolerance_mm"),
                           number(s.get("memory_bytes", 0) / 1e6)))
        for edge, t in sorted(report.get("transitions", {}).items()):
            best = t.get("best", {})
            transitions.append((edge.replace("__", " → "), f"{t.get('rows')}×{t.get('cols')}",
                                number(best.get("similarity"), 3),
                                f"{best.get('from', {}).get('frame')} → {best.get('to', {}).get('frame')}",
                                number(t.get("mean_similarity"), 3)))
    parts.append("<h2>Motion spaces</h2>")
    parts.append(table(["space", "references", "hybrid blend max error (mm)", "linear blend max error (mm)",
                        "tolerance (mm)", "displacement fields (MB)"], spaces) if spaces else "<p>No spaces.</p>")
    parts.append("<p>Errors against the exact non-linear blend at random weights.</p>")
    parts.append("<h2>Transitions</h2>")
    parts.append(table(["edge", "matrix", "best similarity", "best frames", "mean similarity"], transitions)
                 if transitions else "<p>No transitions.</p>")
    return "".join(parts)


def asset_section(out, name):
    parts = ["<h2>Character and playback</h2>"]
    export = summary.load(out, "report/export.json")
    if export:
        c = export["content"]
        rows = [(kind, number(size / 1e6, 3)) for kind, size in sorted(c["buffer_bytes"].items(), key=lambda i: -i[1])]
        parts.append(f"<p>{esc(name)}.glb: {number(c['file_bytes'] / 1e6)} MB, {c['vertices']} vertices, "
                     f"{c['morph_targets']} morph targets, {c['animations']} animations, "
                     f"{'compressed' if c.get('compressed') else 'uncompressed'}.</p>")
        parts.append(table(["content", "MB"], rows))
    play = summary.load(out, "previews/report.json")
    if play:
        per_frame = play.get("evaluation_cpu_per_frame_s", float("nan"))
        text = (f"{play['frames']} frames ({number(play['duration_s'], 1)} s at {play.get('fps')} fps), "
                f"{number(per_frame * 1e6, 0)} µs CPU per frame, planning ≤ {number(play['max_planning_s'] * 1e3)} ms")
        if "check_exact" in play:
            e = play["check_exact"]
            text += (f"; every {e['every']} frames against the exact blend: max {number(e['max_error_mm'])} mm "
                     f"(tolerance {e['tolerance_mm']} mm)")
        parts.append(f"<p>Playback: {esc(text)}.</p>")
        rows = [(t["frame"], f"{t['from']} → {t['to']}", number(t["similarity_cost"], 1), number(t["latency_cost"], 1),
                 number(t["similarity"], 3), t["latency_frames"], number(t["planning_s"] * 1e3, 3))
                for t in play.get("transitions", [])]
        if rows:
            parts.append(table(["frame", "transition", "E_S", "λE_L", "similarity", "latency (frames)",
                                "planning (ms)"], rows))
    times = summary.stage_times(out)
    if times:
        rows = [(stage, count, number(total, 1), number(span, 1), "–" if cpu is None else number(cpu, 1))
                for stage, (count, total, span, cpu) in times.items()]
        parts.append("<h2>Time per stage</h2>")
        parts.append(table(["stage", "steps", "sum of wall times (s)", "first start → last end (s)", "CPU (s)"], rows))
    return "".join(parts)


def previews_section(out):
    pngs = []
    for directory, folders, files in os.walk(out):
        if "capture.json" in files:  # the capture folder is input, not a preview
            folders[:] = []
            continue
        folders.sort()
        pngs += [os.path.join(directory, f) for f in sorted(files) if f.endswith(".png") and not f.startswith(".")]
    parts = ["<h2>Previews</h2>"]
    for path in pngs:
        with open(path, "rb") as handle:
            data = base64.b64encode(handle.read()).decode("ascii")
        label = os.path.relpath(path, out)
        parts.append(f'<figure><img alt="{esc(label)}" src="data:image/png;base64,{data}">'
                     f"<figcaption>{esc(label)}</figcaption></figure>")
    return "".join(parts) if pngs else ""


def module_map(three_root):
    """Import map of data: URLs for the viewer's modules and every module they import."""
    package = os.path.join(three_root, "node_modules", "three")
    keys = {}  # file path → import-map key
    sources = {}

    def key_of(path):
        path = os.path.normpath(path)
        for key, relative in VIEWER_MODULES.items():
            if os.path.normpath(os.path.join(package, relative)) == path:
                return key
        return "surfcap-vendor/three/" + os.path.relpath(path, package)

    def visit(path):
        path = os.path.normpath(path)
        if path in keys:
            return keys[path]
        keys[path] = key_of(path)
        with open(path, encoding="utf-8") as handle:
            text = handle.read()

        def rewrite(match):
            specifier = match.group(3)
            if specifier.startswith("."):
                specifier = visit(os.path.join(os.path.dirname(path), specifier))
            return f"{match.group(1)}{match.group(2)}{specifier}{match.group(2)}"

        sources[keys[path]] = IMPORT.sub(rewrite, text)
        return keys[path]

    for relative in VIEWER_MODULES.values():
        visit(os.path.join(package, relative))
    return {key: "data:text/javascript;base64," + base64.b64encode(text.encode("utf-8")).decode("ascii")
            for key, text in sorted(sources.items())}


def viewer_section(out, name, three_root):
    glbs = [("glb-character", os.path.join(out, f"{name}.glb")),
            ("glb-animation", os.path.join(out, "previews", "animation.glb"))]
    glbs = [(i, p) for i, p in glbs if os.path.exists(p)]
    if not glbs:
        return "<h2>Viewer</h2><p>No .glb file yet.</p>"
    if not three_root or not os.path.exists(os.path.join(three_root, "node_modules", "three", "package.json")):
        return ("<h2>Viewer</h2><p>three.js is not vendored (scripts/vendor_three.sh needs npm): "
                "open the .glb files in a glTF viewer instead.</p>")
    with open(os.path.join(three_root, "node_modules", "three", "package.json"), encoding="utf-8") as handle:
        version = json.load(handle)["version"]
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "report_viewer.js"), encoding="utf-8") as handle:
        viewer = handle.read()
    parts = ["<h2>Viewer</h2>",
             f"<p>three.js {esc(version)} (inlined). Drag to orbit, scroll to zoom. "
             "<label>Clip <select id=\"viewer-clip\"></select></label></p>",
             '<div id="viewer"></div><pre id="viewer-status">loading…</pre>']
    for element, path in glbs:
        with open(path, "rb") as handle:
            data = base64.b64encode(handle.read()).decode("ascii")
        parts.append(f'<script type="application/octet-stream" id="{element}">{data}</script>')
    parts.append('<script type="importmap">' + json.dumps({"imports": module_map(three_root)}) + "</script>")
    parts.append(f'<script type="module">{viewer}</script>')
    return "".join(parts)


STYLE = """body{font-family:sans-serif;margin:1.5em;max-width:1200px;color:#222}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:3px 8px;text-align:left}
th{background:#eee}figure{display:inline-block;margin:.5em}img{max-width:1150px}
#viewer{width:900px;height:560px;border:1px solid #ccc}#viewer-status{font-size:11px;max-height:12em;overflow:auto}"""


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("out")
    parser.add_argument("--name", default="character")
    parser.add_argument("--three", help="folder holding node_modules/three")
    parser.add_argument("--output", help="default OUT/report/index.html")
    args = parser.parse_args()
    output = args.output or os.path.join(args.out, "report", "index.html")
    lines, _ = summary.quality(args.out, args.name)
    figures = table(["", ""], lines) if lines else "<p>No stage report yet.</p>"
    page = ("<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; img-src data: blob:; "
            "style-src 'unsafe-inline'; script-src 'unsafe-inline' 'wasm-unsafe-eval' data:\">"
            f"<title>surfcap run report — {esc(args.name)}</title><style>{STYLE}</style></head><body>"
            f"<h1>surfcap run report — {esc(args.name)}</h1><p>{esc(os.path.abspath(args.out))}</p>"
            + viewer_section(args.out, args.name, args.three) + f"<h2>Figures</h2>{figures}"
            + alignment_section(args.out) + models_section(args.out) + asset_section(args.out, args.name)
            + previews_section(args.out) + "</body></html>")
    os.makedirs(os.path.dirname(os.path.abspath(output)), exist_ok=True)
    temporary = os.path.join(os.path.dirname(os.path.abspath(output)), f".{os.path.basename(output)}.tmp-{os.getpid()}")
    with open(temporary, "w", encoding="utf-8") as handle:
        handle.write(page)
    os.replace(temporary, output)
    print(output)


if __name__ == "__main__":
    sys.exit(main())
