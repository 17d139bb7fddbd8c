#!/usr/bin/env python3
"""tools/arkit_table.py: rewrites the per-shape table of docs/arkit.md from
assets/arkit/default.arkit.json, and the solved-preset table of docs/facs.md from the numbers
in assets/expressions/default.library.json's descriptions (run by tools/make-library.sh after
make-library; standard library only). docs/arkit.md rows keep the file's order: name, how,
mean distance, the neutral's, ratio, the three largest activations, note."""
import json
import os
import re
import sys

LIBRARY = "assets/expressions/default.library.json"
FACS = "docs/facs.md"
FACS_HEADER = "| preset | real shape | rig | neutral | ratio | motion cosine |"
SOLVED = re.compile(r"solved on (?:ICT-FaceKit's )?(\w+) \+ (\w+)\. Mean distance to it ([0-9.]+) cm "
                    r"against ([0-9.]+) cm for the neutral \(ratio ([0-9.]+)\), motion cosine ([0-9]+\.[0-9]+)")


def replace_table(path, header, body):
    lines = open(path).read().split("\n")
    try:
        start = lines.index(header)
    except ValueError:
        sys.exit(f"{path}: the table header line was not found")
    end = start + 2
    while end < len(lines) and lines[end].startswith("|"):
        end += 1
    text = "\n".join(lines[:start + 2] + body + lines[end:])
    tmp = path + ".tmp"
    open(tmp, "w").write(text)
    os.replace(tmp, path)


def facs():
    rows = []
    for e in json.load(open(LIBRARY))["expressions"]:
        m = SOLVED.search(e.get("description", ""))
        if not m:
            continue
        a, b, rig, neutral, ratio, cosine = m.groups()
        pair = f"{a} + _{b.rsplit('_', 1)[1]}" if a.rsplit("_", 1)[0] == b.rsplit("_", 1)[0] else f"{a} + {b}"
        rows.append(f"| {e['name']} | {pair} | {rig} | {neutral} | {ratio} | {cosine} |")
    replace_table(FACS, FACS_HEADER, rows)
    print(f"rewrote the solved-preset table of {FACS} ({len(rows)} presets)")

MAP = "assets/arkit/default.arkit.json"
DOC = "docs/arkit.md"
HEADER = "| ARKit name | how | mean distance (cm) | neutral's (cm) | ratio | activations (largest three) | note |"


def row(name, e):
    acts = sorted(e.get("activations", {}).items(), key=lambda kv: (-kv[1], kv[0]))[:3]
    act = ", ".join(f"{k} {v:.2f}" for k, v in acts) or "-"
    if e["how"] == "solved":
        d, n, r = f"{e['mean_distance']:.4f}", f"{e['neutral_mean_distance']:.4f}", f"{e['ratio']:.2f}"
    else:
        d = n = r = "-"
    return f"| {name} | {e['how']} | {d} | {n} | {r} | {act} | {e.get('note', '')} |"


def main():
    shapes = json.load(open(MAP))["shapes"]
    lines = open(DOC).read().split("\n")
    try:
        start = lines.index(HEADER)
    except ValueError:
        sys.exit(f"{DOC}: the table header line was not found")
    end = start + 2
    while end < len(lines) and lines[end].startswith("|"):
        end += 1
    table = [HEADER, "|---|---|---|---|---|---|---|"] + [row(k, v) for k, v in shapes.items()]
    text = "\n".join(lines[:start] + table + lines[end:])
    tmp = DOC + ".tmp"
    open(tmp, "w").write(text)
    os.replace(tmp, DOC)
    print(f"rewrote the table of {DOC} ({len(shapes)} shapes)")
    facs()


if __name__ == "__main__":
    main()
