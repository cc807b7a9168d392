#!/usr/bin/env python3
"""Summary of a pipelines/character.mk build: quality figures from the stage reports, the wall
time of every stage (from OUT/report/steps.tsv) and where the results are.

  summary.py OUT [--name character] [--json FILE]

Only what the reports hold is printed; a stage that has not run is left out.
"""
import argparse
import collections
import json
import os
import sys


def load(out, path):
    path = os.path.join(out, path)
    if not os.path.exists(path):
        return None
    with open(path, encoding="utf-8") as handle:
        return json.load(handle)


def stage_times(out):
    """{stage: (steps, sum of step seconds, first start → last end seconds, CPU seconds)} in the
    order run; CPU is None when the log has no CPU columns."""
    path = os.path.join(out, "report", "steps.tsv")
    if not os.path.exists(path):
        return {}
    steps = collections.OrderedDict()
    with open(path, encoding="utf-8") as handle:
        for line in handle:
            fields = line.rstrip("\n").split("\t")
            if fields[4] != "0":
                continue
            cpu = sum(float(f) for f in fields[5:7]) if len(fields) >= 7 else None
            steps.setdefault(fields[0], []).append((float(fields[2]), float(fields[3]), cpu))
    times = {}
    for stage, spans in steps.items():
        cpus = [c for _, _, c in spans]
        times[stage] = (len(spans), sum(e - s for s, e, _ in spans),
                        max(e for _, e, _ in spans) - min(s for s, _, _ in spans),
                        None if None in cpus else sum(cpus))
    return times


def quality(out, name):
    """The figures worth a line each, as (label, text) pairs, and the same as a JSON object. A
    report without a figure this script expects gives a line saying so, not a failure."""
    lines, figures = [], {}
    for section in (alignment_lines, model_lines, asset_lines):
        try:
            section(out, lines, figures)
        except (KeyError, TypeError, ValueError) as error:
            lines.append((section.__name__.replace("_lines", ""), f"report not understood ({error!r})"))
    return lines, figures


def alignment_lines(out, lines, figures):
    tree = load(out, "aligned/report/similarity.json")
    if tree and "quality" in tree:
        figures["tree_quality_ratio"] = tree["quality"]["ratio"]
        lines.append(("similarity tree", f"{tree['frames']} frames, root {tree['root']}, quality ratio "
                      f"{tree['quality']['ratio']:.3f} (true deformation along the tree / optimal)"))
    alignment = load(out, "aligned/report/alignment.json")
    if alignment:
        text = f"mean residual {alignment['summary']['mean_residual_m'] * 1000:.2f} mm"
        if "ground_truth" in alignment:
            g = alignment["ground_truth"]
            figures["alignment_rms_percent_height"] = g["rms_percent_height"]
            text = (f"RMS vertex error {g['rms_percent_height']:.2f}% of height, worst frame {g['worst_frame']} "
                    f"{g['worst_frame_rms_percent_height']:.2f}%, " + text)
        lines.append(("alignment", text))


def model_lines(out, lines, figures):
    learn = load(out, "parts/report/learn.json")
    if learn:
        parts = learn.get("parts", {})
        lines.append(("part models", f"{len(parts)} parts from {learn.get('examples')} examples, basis vectors " +
                      ", ".join(f"{part} {p.get('kept')}" for part, p in sorted(parts.items()))))
    report_dir = os.path.join(out, "motion", "report")
    for file in sorted(os.listdir(report_dir)) if os.path.isdir(report_dir) else []:
        report = load(out, os.path.join("motion", "report", file))
        for space, s in sorted(report.get("spaces", {}).items()):
            v = s.get("validation", {})
            figures.setdefault("spaces", {})[space] = {"references": s.get("references"),
                                                       "hybrid_max_error_mm": v.get("hybrid_max_error_mm"),
                                                       "linear_max_error_mm": v.get("linear_max_error_mm")}
            lines.append((f"motion space {space}",
                          f"{s.get('references')} references, blend error at random weights: hybrid "
                          f"{v.get('hybrid_max_error_mm', float('nan')):.2f} mm vs linear "
                          f"{v.get('linear_max_error_mm', float('nan')):.2f} mm (tolerance {s.get('tolerance_mm')} mm), "
                          f"{s.get('memory_bytes', 0) / 1e6:.2f} MB of displacement fields"))
        for edge, t in sorted(report.get("transitions", {}).items()):
            best = t.get("best", {})
            figures.setdefault("transitions", {})[edge] = {"best_similarity": best.get("similarity"),
                                                           "mean_similarity": t.get("mean_similarity")}
            lines.append((f"transition {edge.replace('__', ' → ')}",
                          f"{t.get('rows')}×{t.get('cols')} similarity matrix, best {best.get('similarity', float('nan')):.3f} "
                          f"(frame {best.get('from', {}).get('frame')} → {best.get('to', {}).get('frame')}), "
                          f"mean {t.get('mean_similarity', float('nan')):.3f}"))


def asset_lines(out, lines, figures):
    export = load(out, "report/export.json")
    if export:
        c = export["content"]
        buffers = c["buffer_bytes"]
        figures["asset_bytes"] = c["file_bytes"]
        largest = sorted(buffers.items(), key=lambda item: -item[1])[:3]
        lines.append(("character", f"{c['file_bytes'] / 1e6:.2f} MB (" +
                      ", ".join(f"{kind} {size / 1e6:.2f} MB" for kind, size in largest) +
                      f"), {c['vertices']} vertices, {c['morph_targets']} morph targets, "
                      f"{c['animations']} animations, {c['parts']} parts"))
    play = load(out, "previews/report.json")
    if play:
        per_frame = play.get("evaluation_cpu_per_frame_s", play.get("evaluation_per_frame_s", float("nan")))
        text = (f"{play['frames']} frames ({play['duration_s']:.1f} s), "
                f"{per_frame * 1e6:.0f} µs CPU per frame, planning ≤ {play['max_planning_s'] * 1e3:.2f} ms")
        if "check_exact" in play:
            e = play["check_exact"]
            figures["playback_max_error_mm"] = e["max_error_mm"]
            text += (f"; every {e['every']} frames against the exact non-linear blend: max "
                     f"{e['max_error_mm']:.2f} mm (tolerance {e['tolerance_mm']} mm)")
        lines.append(("playback", text))
        for t in play["transitions"]:
            figures.setdefault("played_transitions", []).append(t)
            lines.append((f"  at frame {t['frame']}", f"{t['from']} → {t['to']}: cost E_S {t['similarity_cost']:.1f} + "
                          f"λE_L {t['latency_cost']:.1f} (similarity {t['similarity']:.3f}, "
                          f"{t['latency_frames']} frames of latency)"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("out")
    parser.add_argument("--name", default="character")
    parser.add_argument("--json", help="also write the figures and stage times here")
    args = parser.parse_args()
    lines, figures = quality(args.out, args.name)
    width = max((len(label) for label, _ in lines), default=0)
    for label, text in lines:
        print(f"  {label:<{width}}  {text}")
    times = stage_times(args.out)
    if times:
        print("  time per stage: steps, sum of their wall times, first start → last end, CPU (user + system)")
        for stage, (count, total, span, cpu) in times.items():
            cpu_text = "" if cpu is None else f" {cpu:8.1f} s CPU"
            print(f"    {stage:<24} {count:>2} {total:8.1f} s {span:8.1f} s{cpu_text}")
    results = [os.path.join(args.out, path) for path in
               (f"{args.name}.glb", f"{args.name}.png", "previews/animation.glb", "previews/contact_sheet.png")]
    pngs = []
    for directory, folders, files in os.walk(args.out):
        if "capture.json" in files:  # a capture folder inside OUT (demo.sh) is input, not a preview
            folders[:] = []
            continue
        folders.sort()
        pngs += [os.path.join(directory, f) for f in files if f.endswith(".png") and not f.startswith(".")]
    print("  results:", ", ".join(path for path in results if os.path.exists(path)) or "none yet")
    print("  previews:", ", ".join(sorted(set(pngs) - set(results))) or "none")
    if args.json:
        figures["stage_seconds"] = {stage: {"steps": c, "sum_s": t, "wall_s": s, "cpu_s": u}
                                    for stage, (c, t, s, u) in times.items()}
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump(figures, handle, indent=2, sort_keys=True)


if __name__ == "__main__":
    sys.exit(main())
