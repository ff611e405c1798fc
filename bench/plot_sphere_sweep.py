#!/usr/bin/env python3
"""SVG figure of the sphere-fit accuracy sweep (no plotting library needed).

  build/bench/vision_sphere_sweep --seeds 200 --csv sweep.csv
  python3 bench/plot_sphere_sweep.py sweep.csv docs/images/vision_sphere_sweep.svg
"""
import csv
import sys

rows = list(csv.DictReader(open(sys.argv[1])))
levels = sorted({int(r["sigma_max_um"]) for r in rows})
methods = [("free", "#1f77b4"), ("known_radius", "#2ca02c"), ("isotropic_weights", "#ff7f0e"), ("pcl", "#d62728")]
get = {(int(r["sigma_max_um"]), r["method"]): r for r in rows}

W, H, pad = 900, 360, 60
panel_w = (W - 3 * pad) / 2
out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
       f'<rect width="{W}" height="{H}" fill="white"/>']


def panel(x0, title, key, ymax, methods_here, ylabel, ref=None):
    y0, h = 40, H - 110
    out.append(f'<text x="{x0 + panel_w / 2}" y="24" text-anchor="middle" font-size="14">{title}</text>')
    out.append(f'<line x1="{x0}" y1="{y0 + h}" x2="{x0 + panel_w}" y2="{y0 + h}" stroke="black"/>')
    out.append(f'<line x1="{x0}" y1="{y0}" x2="{x0}" y2="{y0 + h}" stroke="black"/>')
    for t in range(6):
        v = ymax * t / 5
        y = y0 + h - h * t / 5
        out.append(f'<text x="{x0 - 6}" y="{y + 4}" text-anchor="end">{v:.2g}</text>')
        out.append(f'<line x1="{x0}" y1="{y}" x2="{x0 + panel_w}" y2="{y}" stroke="#ddd"/>')
    out.append(f'<text x="{x0 - 42}" y="{y0 + h / 2}" transform="rotate(-90 {x0 - 42} {y0 + h / 2})" '
               f'text-anchor="middle">{ylabel}</text>')
    group = panel_w / len(levels)
    bw = group * 0.8 / len(methods_here)
    for i, lv in enumerate(levels):
        gx = x0 + i * group + group * 0.1
        out.append(f'<text x="{x0 + (i + 0.5) * group}" y="{y0 + h + 16}" text-anchor="middle">{lv} um</text>')
        for j, (m, colour) in enumerate(methods_here):
            v = key(get[(lv, m)])
            bh = h * min(v, ymax) / ymax
            out.append(f'<rect x="{gx + j * bw}" y="{y0 + h - bh}" width="{bw - 2}" height="{bh}" fill="{colour}"/>')
    if ref is not None:
        for r, dash in ref:
            y = y0 + h - h * r / ymax
            out.append(f'<line x1="{x0}" y1="{y}" x2="{x0 + panel_w}" y2="{y}" stroke="black" stroke-dasharray="{dash}"/>')
    out.append(f'<text x="{x0 + panel_w / 2}" y="{y0 + h + 34}" text-anchor="middle">point sigma at the grazing limit '
               f'(sigma_max; facing the sensor sigma_max/6)</text>')


cmax = max(float(r["centre_err_rms_um"]) for r in rows)
panel(pad, "centre error RMS vs truth (um)", lambda r: float(r["centre_err_rms_um"]), cmax * 1.1, methods, "um")
panel(2 * pad + panel_w, "predicted / observed centre sigma (z axis)", lambda r: float(r["ratio_z"]), 1.4,
      methods[:3], "ratio", ref=[(1.0, "4 2"), (1.3, "1 3"), (1 / 1.3, "1 3")])
lx = pad
for m, colour in methods:
    out.append(f'<rect x="{lx}" y="{H - 22}" width="12" height="12" fill="{colour}"/>')
    label = {"free": "ramtk, free radius", "known_radius": "ramtk, known radius",
             "isotropic_weights": "ramtk, sigmas read isotropic", "pcl": "PCL SACSegmentation (optimized)"}[m]
    out.append(f'<text x="{lx + 16}" y="{H - 12}">{label}</text>')
    lx += 210
out.append("</svg>")
open(sys.argv[2], "w").write("\n".join(out) + "\n")
