#!/usr/bin/env python3
"""What pipelines/character.mk needs to know before any step runs, read from its inputs.

  plan.py frames CAPTURE            total frame count of CAPTURE/capture.json
  plan.py sequences CAPTURE         sequence names, one per line
  plan.py blocks CAPTURE B          B similarity row blocks as a:b ranges (fewer when frames < B)
  plan.py spaces GRAPH              motion space names of a graph config
  plan.py edges GRAPH               transitions of a graph config as FROM__TO
  plan.py files CAPTURE             every file of the capture (not ground_truth/), relative to it

Errors go to stderr with exit 2 (bad argument) or 3 (bad input) so make stops with the reason.
"""
import json
import os
import sys


def fail(code, message):
    print(f"plan.py: {message}", file=sys.stderr)
    sys.exit(code)


def load(path, kind):
    try:
        with open(path, encoding="utf-8") as handle:
            document = json.load(handle)
    except OSError as error:
        fail(3, f"'{path}': {error.strerror}")
    except json.JSONDecodeError as error:
        fail(3, f"'{path}': not JSON ({error})")
    if not str(document.get("format", "")).startswith(f"surfcap.{kind}/"):
        fail(3, f"'{path}': format is {document.get('format')!r}, expected surfcap.{kind}/<n>")
    return document


def capture(folder):
    path = folder if folder.endswith(".json") else os.path.join(folder, "capture.json")
    return load(path, "capture")


def blocks(frames, count):
    count = max(1, min(count, frames))
    bounds = [frames * k // count for k in range(count + 1)]
    return [f"{bounds[k]}:{bounds[k + 1]}" for k in range(count)]


def main(argv):
    if len(argv) < 3:
        fail(2, __doc__)
    command, source = argv[1], argv[2]
    if command == "frames":
        print(sum(int(s["count"]) for s in capture(source)["sequences"]))
    elif command == "sequences":
        print("\n".join(s["name"] for s in capture(source)["sequences"]))
    elif command == "blocks":
        if len(argv) != 4 or not argv[3].isdigit() or int(argv[3]) < 1:
            fail(2, "blocks CAPTURE B: B must be a positive integer")
        print(" ".join(blocks(sum(int(s["count"]) for s in capture(source)["sequences"]), int(argv[3]))))
    elif command == "spaces":
        print("\n".join(space["name"] for space in load(source, "graph_config")["spaces"]))
    elif command == "edges":
        graph = load(source, "graph_config")
        print("\n".join(f"{t['from']}__{t['to']}" for t in graph.get("transitions", [])))
    elif command == "files":
        root = os.path.dirname(source) if source.endswith(".json") else source
        found = []
        for directory, folders, names in os.walk(root):
            folders[:] = sorted(f for f in folders if not (directory == root and f == "ground_truth"))
            found += [os.path.relpath(os.path.join(directory, name), root) for name in sorted(names)]
        print("\n".join(name.replace(" ", "\\ ") for name in found))
    else:
        fail(2, f"unknown command {command!r}\n{__doc__}")


if __name__ == "__main__":
    main(sys.argv)
