#!/usr/bin/python3
"""Reads an ASTM D6673 / AAMA pattern DXF back with ezdxf (an independent
reader) and checks it against the SVG of the same pattern.

usage: check_industry_dxf.py PATTERN.dxf PATTERN.svg PROFILE(astm|aama)

Checks: numbered layers only; one BLOCK per piece, each inserted once; per
piece, the cutting line (layer 1) and the sewing line (layer 14), moved by
its INSERT, within 0.1 mm of the SVG's paths (vertex by vertex); notches on
layer 4 (POINT with an angle for astm, LINE for aama) as many as the SVG's,
each on the cutting line; the piece text and the style text, in 7-bit ASCII.
Prints one JSON line of figures; exits 1 with a message on the first failure.
"""
import json
import math
import re
import sys
import xml.etree.ElementTree as ET

import ezdxf

NS = {"s": "http://www.w3.org/2000/svg"}
TOL_MM = 0.1


def fail(msg):
    print("check_industry_dxf: " + msg, file=sys.stderr)
    sys.exit(1)


def svg_pieces(path):
    root = ET.parse(path).getroot()
    height = float(root.get("viewBox").split()[3])
    pieces = {}
    for g in root.findall("s:g", NS):
        name = g.get("id")

        def poly(d):
            pts = [tuple(map(float, m.split(","))) for m in re.findall(r"-?[\d.]+,-?[\d.]+", d)]
            return [(x, height - y) for x, y in pts]

        cut = [poly(p.get("d")) for p in g.findall("s:path[@class='cut']", NS)]
        sew = [poly(p.get("d")) for p in g.findall("s:path[@class='sew']", NS)]
        notches = len(g.findall("s:line[@class='notch']", NS))
        pieces[name] = {"cut": cut, "sew": sew, "notches": notches}
    return pieces


def seg_dist(p, a, b):
    ax, ay = b[0] - a[0], b[1] - a[1]
    l2 = ax * ax + ay * ay
    t = 0.0 if l2 == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * ax + (p[1] - a[1]) * ay) / l2))
    return math.dist(p, (a[0] + t * ax, a[1] + t * ay))


def poly_dist(p, poly):
    return min(seg_dist(p, poly[i], poly[(i + 1) % len(poly)]) for i in range(len(poly)))


def same_polygon(a, b):
    """Largest vertex-to-vertex distance of two polygons with the same vertices in the same order."""
    if len(a) != len(b):
        return math.inf
    return max(math.dist(p, q) for p, q in zip(a, b))


def main():
    dxf_path, svg_path, profile = sys.argv[1], sys.argv[2], sys.argv[3]
    raw = open(dxf_path, "rb").read()
    if any(c > 0x7E or (c < 0x20 and c not in (0x0A, 0x0D)) for c in raw):
        fail("the DXF is not 7-bit ASCII text")
    doc = ezdxf.readfile(dxf_path)
    svg = svg_pieces(svg_path)
    layers = sorted({e.dxf.layer for e in doc.modelspace()} |
                    {e.dxf.layer for b in doc.blocks if not b.name.startswith("*") for e in b})
    if not all(re.fullmatch(r"\d+", l) for l in layers):
        fail("non-numbered layers: %s" % layers)
    blocks = [b for b in doc.blocks if not b.name.startswith("*")]
    inserts = [e for e in doc.modelspace() if e.dxftype() == "INSERT"]
    if len(blocks) != len(svg):
        fail("%d blocks for %d pieces" % (len(blocks), len(svg)))
    counts = {}
    for e in inserts:
        counts[e.dxf.name] = counts.get(e.dxf.name, 0) + 1
    if sorted(counts) != sorted(b.name for b in blocks) or any(c != 1 for c in counts.values()):
        fail("blocks are not inserted once each: %s" % counts)
    worst = 0.0
    notch_total = 0
    texts_seen = 0
    for b in blocks:
        name = b.name.replace("_", "-")
        if name not in svg:
            fail("block %s has no SVG piece" % b.name)
        ins = next(e for e in inserts if e.dxf.name == b.name).dxf.insert
        off = (ins.x, ins.y)

        def plines(layer):
            out = []
            for e in b.query('POLYLINE[layer=="%s"]' % layer):
                if not e.is_closed:
                    fail("open polyline on layer %s in %s" % (layer, b.name))
                out.append([(v.dxf.location.x + off[0], v.dxf.location.y + off[1]) for v in e.vertices])
            return out

        cut, sew = plines("1"), plines("14")
        ref = svg[name]
        ref_cut = ref["cut"] if ref["cut"] else ref["sew"]
        if len(cut) != len(ref_cut) or len(sew) != len(ref["sew"]):
            fail("%s: %d/%d cutting and %d/%d sewing lines" % (b.name, len(cut), len(ref_cut), len(sew), len(ref["sew"])))
        for mine, theirs in list(zip(cut, ref_cut)) + list(zip(sew, ref["sew"])):
            d = same_polygon(mine, theirs)
            worst = max(worst, d)
            if d > TOL_MM:
                fail("%s: outline %.4f mm from the SVG's" % (b.name, d))
        # Turn and curve points: one per vertex of the cutting lines.
        pts = len(b.query('POINT[layer=="2"]')) + len(b.query('POINT[layer=="3"]'))
        if pts != sum(len(c) for c in cut):
            fail("%s: %d turn/curve points for %d cutting-line vertices" % (b.name, pts, sum(len(c) for c in cut)))
        if profile == "astm":
            notches = b.query('POINT[layer=="4"]')
            where = [(n.dxf.location.x + off[0], n.dxf.location.y + off[1]) for n in notches]
            for n in notches:
                if not n.dxf.hasattr("angle"):
                    fail("%s: a notch point without its angle" % b.name)
        else:
            notches = b.query('LINE[layer=="4"]')
            where = [(n.dxf.start.x + off[0], n.dxf.start.y + off[1]) for n in notches]
        if len(notches) != ref["notches"]:
            fail("%s: %d notches, the SVG has %d" % (b.name, len(notches), ref["notches"]))
        for p in where:
            d = min(poly_dist(p, c) for c in cut)
            if d > TOL_MM:
                fail("%s: a notch %.3f mm off the cutting line" % (b.name, d))
        notch_total += len(notches)
        if len(b.query('LINE[layer=="7"]')) != 1:
            fail("%s: not one grain line" % b.name)
        text = [t.dxf.text for t in b.query('TEXT[layer=="1"]')]
        keys = [t.split(":")[0] + ":" for t in text]
        want = ["Piece Name:", "Quantity:", "Size:", "Category:", "Fabric:", "Annotation:"]
        if keys != want:
            fail("%s: piece text %s" % (b.name, text))
        if text[0] != "Piece Name: " + name.replace("-", " "):
            fail("%s: %s" % (b.name, text[0]))
        texts_seen += 1
    style = [e.dxf.text for e in doc.modelspace() if e.dxftype() == "TEXT"]
    want = ["Style Name:", "Creation Date:", "Author:", "Sample Size:", "Units:"]
    if [s.split(":")[0] + ":" for s in style] != want or style[-1] != "Units: METRIC":
        fail("style text %s" % style)
    print(json.dumps({"blocks": len(blocks), "worst_mm": worst, "notches": notch_total, "layers": layers,
                      "style": style}))


if __name__ == "__main__":
    main()
