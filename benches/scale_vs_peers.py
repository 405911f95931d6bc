#!/usr/bin/env python3
"""Scale of skinpath's jobs against peers in the same run (issue 43, item 4).

Three series, each doubling the work, each beside a peer on the same input, each timed as a
whole process (wall and CPU time, median of --runs) with its peak memory (max RSS):

- drawings: an SVG of N hairline paths (random cubic strokes, 0.1 mm wide, 38 x 38 cm
  page), `skinpath build D.svg --machine grbl-laser` (import, line cuts, ordering, check)
  beside `vpype read D.svg linemerge linesort gwrite` (vpype-gcode's `gcode` profile);
- text: N characters of sans text at 5 mm (lines of about 30 characters, 16 lines for
  489), `skinpath build T.toml --machine BIG.toml` (skin, union, arcs, ordering, check) on
  grbl-laser with a 2 x 2 m work area (written next to the inputs), without `--fit`: the
  glyphs keep their size, so doubling the characters doubles the same work (`--fit` would
  shrink the glyphs of a longer text and build twice), beside `vpype text` of the same
  characters (Hershey "futural", centre lines only: no outline, no union) linemerge
  linesort gwrite;
- hatch: the hairpin of examples/loop.toml filled at 0.04, 0.02 and 0.01 mm (doubling the
  rows)
  (`skinpath build --machine grbl-laser`) beside a plain scanline hatch of the same
  polygon in shapely (GEOS `intersection` of the lines with the polygon; the polygon is
  skinpath's outline of the hairpin, read from `skinpath outline -o out.json`).

Run (release binary built first; peers from pip: vpype, vpype-gcode, shapely):
    python3 benches/scale_vs_peers.py --skinpath target/release/skinpath --runs 3
Not part of CI: it prints machine-dependent times as a markdown table.
"""

import argparse
import json
import os
import random
import shutil
import statistics
import subprocess
import sys
import tempfile

WORDS = (
    "the quick brown fox jumps over a lazy dog while seven wizards box and vex a jolly "
    "king quietly making graphs from the marble of old towns laser engraving needs plain "
    "steady words"
).split()


def timed(cmd, runs):
    """Median wall and CPU seconds and the largest max RSS (MB) of `cmd` over `runs` runs,
    read from GNU time; None when the command fails."""
    walls, cpus, rss = [], [], 0
    for _ in range(runs):
        with tempfile.NamedTemporaryFile("r") as t:
            full = ["/usr/bin/time", "-o", t.name, "-f", "%e %U %S %M"] + cmd
            r = subprocess.run(full, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
            if r.returncode != 0:
                sys.stderr.write(f"failed: {' '.join(cmd)}\n{r.stderr.decode()[-2000:]}\n")
                return None
            w, u, s, m = t.read().split()[-4:]
            walls.append(float(w))
            cpus.append(float(u) + float(s))
            rss = max(rss, int(m) / 1024)
    return statistics.median(walls), statistics.median(cpus), rss


def drawing(path, n, seed=7):
    """An SVG of `n` hairline cubic strokes on a 380 x 380 mm page."""
    rnd = random.Random(seed)
    parts = [
        '<svg xmlns="http://www.w3.org/2000/svg" width="380mm" height="380mm" '
        'viewBox="0 0 380 380"><g fill="none" stroke="#000" stroke-width="0.1">'
    ]
    for _ in range(n):
        x, y = rnd.uniform(10, 355), rnd.uniform(10, 370)
        # Gentle S-curves running left to right (no cusps: the random cubics with loops
        # and cusps trip a tiny-arc refusal of the line fit, noted in the report).
        pts = [(x, y)] + [(x + 4 * k + rnd.uniform(-1, 1), y + rnd.uniform(-3, 3)) for k in (1, 2, 3)]
        d = "M {:.3f} {:.3f} C {:.3f} {:.3f} {:.3f} {:.3f} {:.3f} {:.3f}".format(
            *[c for p in pts for c in p]
        )
        parts.append(f'<path d="{d}"/>')
    parts.append("</g></svg>")
    with open(path, "w") as f:
        f.write("\n".join(parts))


def text(n, lines, seed=3):
    """`n` characters of words in `lines` lines (line breaks counted)."""
    rnd = random.Random(seed)
    per = n // lines
    out = []
    for i in range(lines):
        want = per - 1 if i < lines - 1 else n - per * (lines - 1)
        s = ""
        while len(s) < want:
            s += rnd.choice(WORDS) + " "
        s = s[:want]
        out.append(s[:-1] + "e" if s.endswith(" ") else s)
    return "\n".join(out)


def hatch_script(json_path, spacing):
    """A Python program hatching the outline in `json_path` with shapely at `spacing`."""
    return f"""
import json, shapely
from shapely.geometry import Polygon, MultiLineString
doc = json.load(open({json_path!r}))
rings = [c["points"] for s in doc["strokes"] for c in s["contours"] if c["role"] == "outline"]
poly = shapely.union_all([Polygon(r).buffer(0) for r in rings])
x0, y0, x1, y1 = poly.bounds
lines, y = [], y0 + {spacing} / 2
while y < y1:
    lines.append([(x0 - 1, y), (x1 + 1, y)])
    y += {spacing}
cut = poly.intersection(MultiLineString(lines))
print(len(getattr(cut, "geoms", [cut])))
"""


def row(name, work, ours, peer):
    def cell(t):
        if isinstance(t, str):
            return t
        return "failed" if t is None else f"{t[0]:.3f} / {t[1]:.3f} / {t[2]:.0f}"

    return f"| {name} | {work} | {cell(ours)} | {cell(peer)} |"


def ratios(label, series):
    """Time-doubling ratios (CPU time) of consecutive rows of a series."""
    out = []
    for (w0, a), (w1, b) in zip(series, series[1:]):
        if a and b and a[1] > 0:
            out.append(f"{label} {w0} -> {w1}: x{b[1] / a[1]:.2f} (wall x{b[0] / a[0]:.2f})")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skinpath", default="target/release/skinpath")
    ap.add_argument("--vpype", default=shutil.which("vpype") or "vpype")
    ap.add_argument("--python", default=sys.executable, help="a Python with shapely")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--paths", default="2500,5000,10000")
    ap.add_argument("--chars", default="489,978,1956")
    ap.add_argument("--spacings", default="0.04,0.02,0.01")
    ap.add_argument("--loop", default="examples/loop.toml")
    a = ap.parse_args()
    sp = os.path.abspath(a.skinpath)
    tmp = tempfile.mkdtemp(prefix="skinpath-scale-")
    lines = ["| job | work | skinpath wall s / CPU s / MB | peer wall s / CPU s / MB |", "|---|---|---|---|"]
    notes = []

    series = []
    for n in map(int, a.paths.split(",")):
        svg = os.path.join(tmp, f"d{n}.svg")
        drawing(svg, n)
        ours = timed([sp, "build", svg, "--machine", "grbl-laser", "-o", os.path.join(tmp, "d.gcode")], a.runs)
        peer = timed([a.vpype, "read", svg, "linemerge", "linesort", "gwrite", "-p", "gcode", os.path.join(tmp, "v.gcode")], a.runs)
        lines.append(row("drawing (vpype)", f"{n} paths", ours, peer))
        series.append((n, ours))
    notes += ratios("paths", series)

    big = os.path.join(tmp, "grbl-laser-big.toml")
    machines = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "machines")
    with open(os.path.join(machines, "grbl-laser.toml")) as f:
        profile = f.read().replace("[0.0, 400.0]", "[0.0, 2000.0]")
    with open(big, "w") as f:
        f.write(profile.replace('name = "grbl-laser"', 'name = "grbl-laser-big"'))
    series = []
    for n in map(int, a.chars.split(",")):
        body = text(n, max(1, round(16 * n / 489)))
        toml = os.path.join(tmp, f"t{n}.toml")
        with open(toml, "w") as f:
            f.write('version = 1\nunits = "mm"\n\n[[text]]\nname = "t"\n')
            f.write(f'text = """{body}"""\nheight = 5.0\nwidth = 0.5\n')
        ours = timed([sp, "build", toml, "--machine", big, "-o", os.path.join(tmp, "t.gcode")], a.runs)
        peer = timed([a.vpype, "text", "-s", "7mm", body.replace("\n", " "), "pagesize", "380mmx380mm", "linemerge", "linesort", "gwrite", "-p", "gcode", os.path.join(tmp, "vt.gcode")], a.runs)
        lines.append(row("text (vpype text)", f"{n} chars", ours, peer))
        series.append((n, ours))
    notes += ratios("chars", series)
    # The issue's own case: 489 characters fitted to 380 x 380 mm on grbl-laser (two builds).
    toml = os.path.join(tmp, "t489.toml")
    if os.path.exists(toml):
        fit = timed([sp, "build", toml, "--machine", "grbl-laser", "--fit", "380x380", "-o", os.path.join(tmp, "t.gcode")], a.runs)
        lines.append(row("text, `--fit 380x380` on grbl-laser", "489 chars", fit, "(no peer run)"))

    outline = os.path.join(tmp, "loop.json")
    subprocess.run([sp, "outline", a.loop, "-o", outline], check=True, stderr=subprocess.DEVNULL)
    with open(a.loop) as f:
        base = "".join(l for l in f if not l.startswith(("[outline]", "method", "tolerance")))
    series = []
    for s in a.spacings.split(","):
        toml = os.path.join(tmp, f"h{s}.toml")
        with open(toml, "w") as f:
            f.write(base + f'\n[[operation]]\nkind = "fill"\nspacing = {s}\n')
        ours = timed([sp, "build", toml, "--machine", "grbl-laser", "-o", os.path.join(tmp, "h.gcode")], a.runs)
        script = os.path.join(tmp, f"hatch{s}.py")
        with open(script, "w") as f:
            f.write(hatch_script(outline, float(s)))
        peer = timed([a.python, script], a.runs)
        lines.append(row("hatch (shapely scanline)", f"{s} mm", ours, peer))
        series.append((s, ours))
    notes += ratios("hatch", series)

    print("\n".join(lines))
    print()
    print("\n".join(notes))
    shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
