#!/usr/bin/env python3
"""Turns Google Benchmark JSON into a markdown table of medians (one row per benchmark)."""
import json
import sys


def human_time(value, unit):
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[unit]
    seconds = value * scale
    for name, factor in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6), ("ns", 1e-9)):
        if seconds >= factor:
            return f"{seconds / factor:.3g} {name}"
    return f"{seconds / 1e-9:.3g} ns"


def main(path):
    with open(path) as handle:
        results = json.load(handle)
    context = results.get("context", {})
    print(f"Benchmarks on {context.get('host_name', '?')}, {context.get('num_cpus', '?')} CPUs, "
          f"{context.get('date', '')}. Medians of the repetitions.\n")
    print("| benchmark | real time (median) | CPU time (median) | counters |")
    print("|---|---|---|---|")
    rows = [b for b in results.get("benchmarks", []) if b.get("aggregate_name", "median") == "median"]
    skip = {"name", "run_name", "run_type", "repetitions", "repetition_index", "threads", "iterations",
            "real_time", "cpu_time", "time_unit", "aggregate_name", "aggregate_unit", "family_index",
            "per_family_instance_index", "label", "error_occurred", "error_message"}
    for bench in rows:
        unit = bench.get("time_unit", "ns")
        counters = ", ".join(f"{key}={bench[key]:.4g}" for key in sorted(bench)
                             if key not in skip and isinstance(bench[key], (int, float)))
        name = bench.get("run_name", bench["name"])
        if bench.get("error_occurred"):
            print(f"| {name} | skipped: {bench.get('error_message', '')} | | |")
            continue
        print(f"| {name} | {human_time(bench['real_time'], unit)} | {human_time(bench['cpu_time'], unit)} | {counters} |")


if __name__ == "__main__":
    main(sys.argv[1])
