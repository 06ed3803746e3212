#!/usr/bin/python3
"""Checks a tiled pattern PDF as a printer would print it.

usage: check_pdf.py PATTERN.pdf REPORT.json SQUARE_MM [SQUARE_MM ...]

Rasterises the first page with pdftoppm (poppler-utils) at 300 DPI and
measures every filled test square (grey 60 %) within 0.5 % of its side; reads
the page count with pdfinfo and each page's text with pdftotext: the cover
names every tile, each printed tile's page carries its label, and the blank
tiles of the report are not printed. Prints one JSON line of figures.
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
from scipy import ndimage

DPI = 300


def fail(msg):
    print("check_pdf: " + msg, file=sys.stderr)
    sys.exit(1)


def read_pgm(path):
    with open(path, "rb") as f:
        data = f.read()
    parts = data.split(maxsplit=4)
    if parts[0] != b"P5":
        fail("not a binary PGM")
    w, h, maxval = int(parts[1]), int(parts[2]), int(parts[3])
    return np.frombuffer(parts[4][: w * h], dtype=np.uint8).reshape(h, w)


def main():
    pdf, report_path, squares = sys.argv[1], sys.argv[2], [float(s) for s in sys.argv[3:]]
    name = os.path.basename(pdf)
    sheet = next(s for s in json.load(open(report_path))["sheets"] if s["file"] == name)
    with tempfile.TemporaryDirectory() as tmp:
        base = os.path.join(tmp, "page")
        subprocess.run(["pdftoppm", "-gray", "-r", str(DPI), "-f", "1", "-l", "1", "-singlefile", pdf, base], check=True)
        img = read_pgm(base + ".pgm")
    grey = (img > 135) & (img < 170)
    labels, n = ndimage.label(grey)
    found = []
    for sl in ndimage.find_objects(labels):
        h = (sl[0].stop - sl[0].start) * 25.4 / DPI
        w = (sl[1].stop - sl[1].start) * 25.4 / DPI
        if w > 20 and h > 20:
            found.append((w, h))
    measured = []
    for side in squares:
        best = min(found, key=lambda wh: abs(wh[0] - side) + abs(wh[1] - side), default=None)
        if best is None:
            fail("no test square on the first page")
        for v in best:
            if abs(v - side) > 0.005 * side:
                fail("test square of %.1f mm measures %.2f x %.2f mm" % (side, best[0], best[1]))
        measured.append(best)
    info = subprocess.run(["pdfinfo", pdf], capture_output=True, text=True, check=True).stdout
    pages = int(next(l.split()[-1] for l in info.splitlines() if l.startswith("Pages:")))
    printed = [t for t in range(sheet["rows"] * sheet["columns"])]
    if pages != sheet["pages"]:
        fail("%d pages, the report says %d" % (pages, sheet["pages"]))
    blank = set(sheet["blank_left_out"])
    if pages != 1 + sheet["rows"] * sheet["columns"] - len(blank):
        fail("%d pages for %d tiles of which %d blank" % (pages, len(printed), len(blank)))
    texts = []
    for p in range(1, pages + 1):
        texts.append(subprocess.run(["pdftotext", "-f", str(p), "-l", str(p), pdf, "-"], capture_output=True,
                                    text=True, check=True).stdout)
    labels_printed = []
    for r in range(sheet["rows"]):
        for c in range(sheet["columns"]):
            label = chr(ord("A") + r) + str(c + 1)
            if label not in blank:
                labels_printed.append(label)
    for k, label in enumerate(labels_printed):
        if (label + "  (") not in texts[k + 1] and (label + " (") not in texts[k + 1]:
            fail("page %d does not carry its label %s" % (k + 2, label))
    if "100 %" not in texts[0] or "Page map" not in texts[0]:
        fail("the cover lacks its instructions or page map")
    print(json.dumps({"pages": pages, "squares_mm": measured, "blank": sorted(blank), "rows": sheet["rows"],
                      "columns": sheet["columns"]}))


if __name__ == "__main__":
    main()
