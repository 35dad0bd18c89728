#!/usr/bin/env python3
"""Draws a flight exported with `uavip export --format geojson` as an offline HTML page
(inline SVG: longitude/latitude graticule, one colour per sortie, photo stops as dots,
home as a square), for a look at where the flight lies before any map is at hand.
Open the page in a browser, or screenshot it headless:
  python3 scripts/geojson_preview.py site.geojson site.html
  chromium --headless --no-sandbox --screenshot=site.png --window-size=1000,800 file://$PWD/site.html
"""
import json
import math
import sys

COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"]


def main(src: str, out: str) -> None:
    with open(src, encoding="utf-8") as f:
        doc = json.load(f)
    pts = []
    for feat in doc["features"]:
        g = feat["geometry"]
        pts += g["coordinates"] if g["type"] == "LineString" else [g["coordinates"]]
    lon0 = sum(p[0] for p in pts) / len(pts)
    lat0 = sum(p[1] for p in pts) / len(pts)
    k = math.cos(math.radians(lat0))  # equirectangular about the site: metres on both axes
    xs = [(p[0] - lon0) * k for p in pts]
    ys = [p[1] - lat0 for p in pts]
    span = max(max(xs) - min(xs), max(ys) - min(ys)) * 1.15 or 1e-5
    w = h = 760
    cx, cy = (max(xs) + min(xs)) / 2, (max(ys) + min(ys)) / 2

    def xy(p):
        return (w / 2 + ((p[0] - lon0) * k - cx) / span * w, h / 2 - ((p[1] - lat0) - cy) / span * h)

    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w + 160}" height="{h + 60}" font-family="sans-serif" font-size="12">',
           f'<rect x="0" y="0" width="{w}" height="{h}" fill="#f4f1ea" stroke="#999"/>']
    step = 10 ** math.floor(math.log10(span / 4))
    lat = math.floor((lat0 + cy - span / 2) / step) * step
    while lat < lat0 + cy + span / 2:
        y = xy((lon0, lat))[1]
        if 0 < y < h:
            svg.append(f'<line x1="0" y1="{y:.1f}" x2="{w}" y2="{y:.1f}" stroke="#ccc"/><text x="{w + 4}" y="{y + 4:.1f}">{lat:.5f}°</text>')
        lat += step
    lon = math.floor((lon0 + (cx - span / 2) / k) / (step / k)) * (step / k)
    n = 0
    while lon < lon0 + (cx + span / 2) / k:
        x = xy((lon, lat0))[0]
        if 0 < x < w:
            label = f'<text x="{x - 36:.1f}" y="{h + 16}">{lon:.5f}°</text>' if n % 2 == 0 else ""
            svg.append(f'<line x1="{x:.1f}" y1="0" x2="{x:.1f}" y2="{h}" stroke="#ccc"/>{label}')
            n += 1
        lon += step / k
    legend = []
    for feat in doc["features"]:
        g, p = feat["geometry"], feat["properties"]
        colour = COLOURS[(p.get("sortie", 1) - 1) % len(COLOURS)]
        if g["type"] == "LineString":
            d = " ".join(f"{x:.1f},{y:.1f}" for x, y in map(xy, g["coordinates"]))
            svg.append(f'<polyline points="{d}" fill="none" stroke="{colour}" stroke-width="1.4"/>')
            legend.append((colour, p.get("name", "path")))
        elif p.get("kind") == "stop":
            x, y = xy(g["coordinates"])
            svg.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="2" fill="{colour}"/>')
        elif p.get("kind") == "home":
            x, y = xy(g["coordinates"])
            svg.append(f'<rect x="{x - 6:.1f}" y="{y - 6:.1f}" width="12" height="12" fill="#fff" stroke="#000" stroke-width="2"/>')
    for i, (colour, name) in enumerate(legend):
        svg.append(f'<rect x="12" y="{14 + 18 * i}" width="14" height="4" fill="{colour}"/><text x="32" y="{20 + 18 * i}">{name}</text>')
    metres = span * 111320 / 4
    svg.append(f'<text x="12" y="{h + 40}">{doc.get("name", "")}: WGS84 longitude/latitude, north up; grid {step * 111320:.0f} m; '
               f'a quarter of the frame is {metres:.0f} m</text></svg>')
    with open(out, "w", encoding="utf-8") as f:
        f.write("<!doctype html><html><body style='margin:0'>" + "\n".join(svg) + "</body></html>\n")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: geojson_preview.py FLIGHT.geojson OUT.html")
    main(sys.argv[1], sys.argv[2])
