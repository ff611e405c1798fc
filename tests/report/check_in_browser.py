#!/usr/bin/env python3
"""Opens an HTML report of ramtk in headless Chromium and checks that it renders.

Checks: no script error and no console.error (the page collects them in data-ramtk-errors), no
"Uncaught" message in Chromium's console log, every chart drawn by Plotly (data-charts-drawn equals
the number of chart containers, each carrying Plotly's class), every expected element id present.
Saves a screenshot and checks it is a PNG of the window's size with content. PNG files given with
--png are checked for their size and for content (not one flat colour, some ink).

Exit codes: 0 pass, 1 fail, 77 skipped (Chromium missing or unable to start; ctest SKIP_RETURN_CODE).
"""
import argparse
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

SKIP = 77


def find_chromium():
    for name in (os.environ.get("CHROMIUM", ""), "chromium", "chromium-browser", "google-chrome"):
        if name and shutil.which(name):
            return shutil.which(name)
    return None


def read_png(path):
    """Width, height and rows of pixels (lists of channel tuples) of an 8-bit non-interlaced PNG."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, width = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or interlace != 0 or colour not in (0, 2, 4, 6):
                raise ValueError(f"{path}: unsupported PNG (depth {depth}, colour {colour}, interlace {interlace})")
            channels = {0: 1, 2: 3, 4: 2, 6: 4}[colour]
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, prev, i = [], bytearray(stride), 0
    for _ in range(height):
        ftype, line = raw[i], bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - channels] if x >= channels else 0
            b = prev[x]
            c = prev[x - channels] if x >= channels else 0
            if ftype == 1:
                line[x] = (line[x] + a) & 255
            elif ftype == 2:
                line[x] = (line[x] + b) & 255
            elif ftype == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif ftype == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return width, height, channels, rows


def check_png(path, width=None, height=None, min_ink=0.01):
    w, h, ch, rows = read_png(path)
    problems = []
    if width and w != width:
        problems.append(f"{path}: width {w}, expected {width}")
    if height and h != height:
        problems.append(f"{path}: height {h}, expected {height}")
    # Ink: pixels that are not the background (the top-left pixel's colour), on a sample grid.
    bg = rows[0][:ch]
    ink = total = 0
    colours = set()
    for y in range(0, h, 3):
        row = rows[y]
        for x in range(0, w, 3):
            px = row[x * ch:(x + 1) * ch]
            total += 1
            colours.add(px)
            if px != bg:
                ink += 1
    if ink / max(total, 1) < min_ink:
        problems.append(f"{path}: nearly blank ({100 * ink / max(total, 1):.2f}% ink)")
    if len(colours) < 8:
        problems.append(f"{path}: only {len(colours)} colours")
    return problems


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("html")
    ap.add_argument("--expect", action="append", default=[], help="element id that must exist (repeatable)")
    ap.add_argument("--screenshot", help="where to save the screenshot (default: beside the report)")
    ap.add_argument("--png", action="append", default=[], help="PNG to check: PATH or PATH:WIDTHxHEIGHT")
    ap.add_argument("--timeout", type=float, default=240)
    args = ap.parse_args()

    problems = []
    for spec in args.png:
        m = re.match(r"^(.*):(\d+)x(\d+)$", spec)
        path, w, h = (m.group(1), int(m.group(2)), int(m.group(3))) if m else (spec, None, None)
        if not os.path.exists(path):
            problems.append(f"{path}: missing")
        else:
            problems += check_png(path, w, h)

    chrome = find_chromium()
    if not chrome:
        print("SKIP: Chromium not found (Debian package chromium; or set CHROMIUM)")
        return SKIP
    url = "file://" + os.path.abspath(args.html)
    with tempfile.TemporaryDirectory() as profile:
        base = [chrome, "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
                "--hide-scrollbars", "--no-first-run", "--user-data-dir=" + profile,
                "--enable-logging=stderr", "--v=0", "--virtual-time-budget=30000"]
        shot = args.screenshot or os.path.join(os.path.dirname(os.path.abspath(args.html)), "screenshot.png")
        size = (1200, 2400)
        if os.path.exists(shot):
            os.remove(shot)
        # One Chromium run gives both the DOM after the scripts ran and the screenshot (two runs
        # until 2026-11-25: each start costs 10-25 s of a CI slot).
        try:
            run = subprocess.run(base + [f"--window-size={size[0]},{size[1]}", "--screenshot=" + shot,
                                         "--dump-dom", url], capture_output=True, text=True, timeout=args.timeout)
        except (OSError, subprocess.TimeoutExpired) as e:
            print(f"SKIP: Chromium could not run: {e}")
            return SKIP
        dom, log = run.stdout, run.stderr
        if run.returncode != 0 or "<html" not in dom:
            print(f"SKIP: Chromium did not start (exit {run.returncode}): {log[-600:]}")
            return SKIP
        if not os.path.exists(shot):
            problems.append(f"no screenshot (exit {run.returncode}): {log[-400:]}")
        else:
            problems += check_png(shot, size[0], size[1], min_ink=0.05)

    m = re.search(r'data-ramtk-errors="(\d+)"', dom)
    if not m:
        problems.append("the page's drawing script did not finish (no data-ramtk-errors on <body>)")
    elif m.group(1) != "0":
        err = re.search(r'id="ramtk-errors">([^<]*)', dom)
        problems.append(f"{m.group(1)} script error(s): {err.group(1) if err else '?'}")
    for line in log.splitlines():
        if "CONSOLE" in line and "Uncaught" in line:
            problems.append("console: " + line.strip())
    containers = len(re.findall(r'class="ramtk-chart[ "]', dom))
    drawn = re.search(r'data-charts-drawn="(\d+)"', dom)
    plotted = len(re.findall(r'class="ramtk-chart js-plotly-plot"', dom))
    if containers == 0 and not args.expect:
        problems.append("no chart in the page")
    if containers and (not drawn or int(drawn.group(1)) != containers):
        problems.append(f"{drawn.group(1) if drawn else 'no'} of {containers} charts reported drawn")
    if plotted != containers:
        problems.append(f"{plotted} of {containers} chart containers hold a Plotly chart")
    for ident in args.expect:
        if f'id="{ident}"' not in dom:
            problems.append(f"element id '{ident}' missing")

    name = os.path.basename(os.path.dirname(os.path.abspath(args.html))) + "/" + os.path.basename(args.html)
    if problems:
        print(f"FAIL {name}:")
        for p in problems:
            print("  - " + p)
        return 1
    print(f"ok {name}: {containers} charts drawn, {len(args.expect)} expected ids present, screenshot {shot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
