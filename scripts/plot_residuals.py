#!/usr/bin/env python3
"""The force residual per Newton iteration of static key poses, as an SVG plot.

    plot_residuals.py OUT.svg LABEL=REPORT.json:POINTER [LABEL=REPORT.json:POINTER ...]

Each series is a JSON pointer into a simulate-adapt report.json that names a key pose solved
statically (`--solver static`, or an in-between frame of the verification), e.g.
`/key_poses/1` or `/verification/key_poses/2`; its `force_residuals` (mean vertex weights, one
per iterate) are drawn on a log scale against the iteration, with the tolerance the report
records (`/options/static_tolerance`) as a dashed line. Standard library only: the machines
have no plotting package.
"""
import json
import math
import sys

COLOURS = ["#1f5fa8", "#c2410c", "#15803d", "#7e22ce"]
W, H = 720, 420
LEFT, RIGHT, TOP, BOTTOM = 70, 20, 30, 50


def pointer_get(doc, pointer):
    node = doc
    for part in pointer.strip("/").split("/"):
        if part == "":
            continue
        node = node[int(part)] if isinstance(node, list) else node[part]
    return node


def find_tolerance(doc):
    for key in ("options", "fit_options"):
        if isinstance(doc.get(key), dict) and "static_tolerance" in doc[key]:
            return float(doc[key]["static_tolerance"])
    return None


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    out = argv[1]
    series, tolerance = [], None
    for arg in argv[2:]:
        if "=" not in arg or ":" not in arg.split("=", 1)[1]:
            sys.exit(f"plot_residuals: {arg}: expected LABEL=REPORT.json:POINTER")
        label, rest = arg.split("=", 1)
        path, pointer = rest.rsplit(":", 1)
        with open(path) as f:
            doc = json.load(f)
        try:
            pose = pointer_get(doc, pointer)
        except (KeyError, IndexError, ValueError):
            sys.exit(f"plot_residuals: {path}: no key pose at {pointer}")
        residuals = pose.get("force_residuals")
        if not residuals or not all(isinstance(r, (int, float)) and r > 0 for r in residuals):
            sys.exit(f"plot_residuals: {path}: {pointer} has no positive force_residuals (not solved statically?)")
        series.append((label, residuals))
        tolerance = tolerance or find_tolerance(doc)
    n = max(len(r) for _, r in series)
    values = [v for _, r in series for v in r] + ([tolerance] if tolerance else [])
    lo = math.floor(math.log10(min(values)))
    hi = math.ceil(math.log10(max(values)))
    if hi == lo:
        hi = lo + 1

    def x(i):
        return LEFT + (W - LEFT - RIGHT) * i / max(n - 1, 1)

    def y(v):
        return TOP + (H - TOP - BOTTOM) * (hi - math.log10(v)) / (hi - lo)

    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
           f'<rect width="{W}" height="{H}" fill="white"/>']
    for e in range(lo, hi + 1):
        svg.append(f'<line x1="{LEFT}" x2="{W - RIGHT}" y1="{y(10 ** e):.1f}" y2="{y(10 ** e):.1f}" stroke="#ddd"/>')
        svg.append(f'<text x="{LEFT - 6}" y="{y(10 ** e) + 4:.1f}" text-anchor="end">1e{e}</text>')
    step = max(1, round(n / 8, -1 if n > 80 else 0))
    for i in range(0, n, int(step)):
        svg.append(f'<text x="{x(i):.1f}" y="{H - BOTTOM + 18}" text-anchor="middle">{i}</text>')
    svg.append(f'<text x="{(LEFT + W - RIGHT) / 2}" y="{H - 12}" text-anchor="middle">Newton iteration</text>')
    svg.append(f'<text x="16" y="{(TOP + H - BOTTOM) / 2}" transform="rotate(-90 16 {(TOP + H - BOTTOM) / 2})" '
               'text-anchor="middle">force residual [mean vertex weights, RMS]</text>')
    if tolerance:
        svg.append(f'<line x1="{LEFT}" x2="{W - RIGHT}" y1="{y(tolerance):.1f}" y2="{y(tolerance):.1f}" '
                   'stroke="#444" stroke-dasharray="6 4"/>')
        svg.append(f'<text x="{W - RIGHT - 4}" y="{y(tolerance) - 5:.1f}" text-anchor="end">tolerance {tolerance:g}</text>')
    for k, (label, r) in enumerate(series):
        colour = COLOURS[k % len(COLOURS)]
        points = " ".join(f"{x(i):.1f},{y(v):.1f}" for i, v in enumerate(r))
        svg.append(f'<polyline fill="none" stroke="{colour}" stroke-width="1.5" points="{points}"/>')
        svg.append(f'<text x="{W - RIGHT - 10}" y="{TOP + 14 + 16 * k}" text-anchor="end" fill="{colour}">'
                   f'{label} ({len(r) - 1} iterations)</text>')
    svg.append("</svg>")
    with open(out, "w") as f:
        f.write("\n".join(svg) + "\n")


if __name__ == "__main__":
    main(sys.argv)
