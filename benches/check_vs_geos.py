#!/usr/bin/env python3
"""`skinpath check` on a 1M-segment program against its peers (issue #16, item 3).

Peers:
- GEOS `is_simple` (through shapely, `pip install shapely`) on the same points already in
  memory: the intersection test alone, no reading or parsing;
- LinuxCNC's stand-alone interpreter `rs274 -n 0 -g` on the same file, when installed.

Two programs, each cut with a laser and written as `G1 X… Y…` lines of about 20 bytes:
- circles: closed 1000-gons of radius 4 on a 9 mm grid (a nesting or lettering job: many
  contours, no intersections; sparse);
- spiral: one Archimedean spiral of 200 turns 0.45 mm apart (a spiral fill or an engraving;
  dense: its half turns all nest), issue #42.

Run (release binary built first):
    python3 benches/check_vs_geos.py --segments 1000000 --skinpath target/release/skinpath
`--pairs 15` also times 15 alternated (GEOS, check, GEOS) runs per program and prints the
median and best ratios, steadier than the ratio of two best-of figures on a busy machine.
Not part of CI: it needs shapely and prints wall times, which are machine-dependent.
"""

import argparse
import math
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

PER_CIRCLE = 1000


def circles(n):
    """Closed 1000-gons (lists of (x, y) rounded to the program's 3 decimals)."""
    k = -(-n // PER_CIRCLE)
    side = math.ceil(math.sqrt(k))
    out = []
    for c in range(k):
        ox, oy = 5.0 + (c % side) * 9.0, 5.0 + (c // side) * 9.0
        pts = []
        for i in range(PER_CIRCLE + 1):
            t = math.tau * (i % PER_CIRCLE) / PER_CIRCLE
            pts.append((round(ox + 4.0 * math.cos(t), 3), round(oy + 4.0 * math.sin(t), 3)))
        out.append(pts)
    return out


def spiral(n):
    """One spiral of 200 turns 0.45 mm apart in `n` chords about (100, 100), rounded as the
    program writes its points."""
    per = n // 200
    pts = []
    for i in range(200 * per + 1):
        t = math.tau * i / per
        r = 0.45 * t / math.tau
        pts.append((round(100.0 + r * math.cos(t), 3), round(100.0 + r * math.sin(t), 3)))
    return [pts]


def write_program(polys, path):
    with open(path, "w") as f:
        f.write("G21 G90 G17\nF1500 S800\n")
        for p in polys:
            f.write("G0 X%.3f Y%.3f\nM4\n" % p[0])
            for x, y in p[1:]:
                f.write("G1 X%.3f Y%.3f\n" % (x, y))
            f.write("M5\n")
        f.write("M2\n")


def cpu():
    """CPU seconds (user + system) of this process and its finished children: on a loaded
    machine wall times mostly measure the other processes."""
    s, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return s.ru_utime + s.ru_stime + c.ru_utime + c.ru_stime


def best_of(k, fn):
    """Best wall time and best CPU time of `k` runs of `fn`."""
    best, best_cpu = math.inf, math.inf
    for _ in range(k):
        t0, c0 = time.perf_counter(), cpu()
        fn()
        best = min(best, time.perf_counter() - t0)
        best_cpu = min(best_cpu, cpu() - c0)
    return best, best_cpu


def bench(a, polys, path):
    """Times `check` of the program of `polys` written to `path` against its peers; returns
    the row of the ratios table (None for a peer not run)."""
    write_program(polys, path)
    size = os.path.getsize(path)
    segs = sum(len(p) - 1 for p in polys)
    print(f"program: {segs} segments, {size / 2**20:.1f} MiB")

    ours, ours_cpu = best_of(
        a.repeat,
        lambda: subprocess.run(
            [a.skinpath, "check", path], stdout=subprocess.DEVNULL, check=False
        ),
    )
    print(
        f"skinpath check (whole process): wall {ours:.3f} s, CPU {ours_cpu:.3f} s, "
        f"{size / 2**20 / ours_cpu:.1f} MiB/s of CPU time"
    )

    row = {"wall": ours, "cpu": ours_cpu, "geos": None, "geos_cpu": None}
    try:
        import shapely

        geom = shapely.MultiLineString(polys)
        geos, geos_cpu = best_of(a.repeat, lambda: shapely.is_simple(geom))
        row["geos"], row["geos_cpu"] = geos, geos_cpu
        print(
            f"GEOS is_simple (points in memory): wall {geos:.3f} s, CPU {geos_cpu:.3f} s; "
            f"skinpath/GEOS wall {ours / geos:.2f}, CPU {ours_cpu / geos_cpu:.2f}"
        )
        if a.pairs:
            paired(a, path, lambda: shapely.is_simple(geom))
    except ImportError:
        print("GEOS: shapely not installed (pip install shapely): skipped")

    rs274 = shutil.which("rs274")
    if rs274:
        t, t_cpu = best_of(
            1,
            lambda: subprocess.run(
                [rs274, "-n", "0", "-g", path],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
                check=False,
            ),
        )
        print(
            f"LinuxCNC rs274 -n 0 -g: wall {t:.3f} s, CPU {t_cpu:.3f} s; "
            f"rs274/skinpath wall {t / ours:.1f}x, CPU {t_cpu / ours_cpu:.1f}x"
        )
    else:
        print("LinuxCNC rs274: not installed here (linuxcnc-uspace): skipped")
    return row


def paired(a, path, geos):
    """Ratios of `check` to GEOS in `a.pairs` alternated runs of (GEOS, check, GEOS), each
    check against the faster GEOS of its pair: on a machine whose speed drifts between runs
    the ratio of one pair is steadier than the ratio of two best-of figures."""
    ratios = []
    for _ in range(a.pairs):
        g1 = best_of(1, geos)
        ours = best_of(
            1,
            lambda: subprocess.run(
                [a.skinpath, "check", path], stdout=subprocess.DEVNULL, check=False
            ),
        )
        g2 = best_of(1, geos)
        ratios.append((ours[0] / min(g1[0], g2[0]), ours[1] / min(g1[1], g2[1])))
    wall = sorted(r[0] for r in ratios)
    cpu = sorted(r[1] for r in ratios)
    print(
        f"{a.pairs} alternated pairs: check/GEOS wall median {wall[len(wall) // 2]:.2f} "
        f"(best {wall[0]:.2f}), CPU median {cpu[len(cpu) // 2]:.2f} (best {cpu[0]:.2f})"
    )


def table(rows):
    """The README's ratios table (best of the runs, seconds) from the rows of `bench`."""
    print("\n| program | check wall | check CPU | GEOS wall | GEOS CPU | wall ratio | CPU ratio |")
    print("|---|---|---|---|---|---|---|")
    for name, r in rows:
        if r["geos"] is None:
            print(f"| {name} | {r['wall']:.3f} | {r['cpu']:.3f} | – | – | – | – |")
            continue
        print(
            f"| {name} | {r['wall']:.3f} | {r['cpu']:.3f} | {r['geos']:.3f} | "
            f"{r['geos_cpu']:.3f} | {r['wall'] / r['geos']:.1f}× | "
            f"{r['cpu'] / r['geos_cpu']:.1f}× |"
        )


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--segments", type=int, default=1_000_000)
    ap.add_argument("--skinpath", default="target/release/skinpath")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--keep", help="write the programs into this folder and keep them")
    ap.add_argument(
        "--pairs",
        type=int,
        default=0,
        help="also time this many alternated (GEOS, check, GEOS) runs and print the ratios",
    )
    a = ap.parse_args()

    tmp = tempfile.mkdtemp(prefix="skinpath-bench-")
    rows = []
    for name, polys in (("circles", circles(a.segments)), ("spiral", spiral(a.segments))):
        print(f"== {name}")
        path = os.path.join(a.keep or tmp, f"{name}.gcode")
        rows.append((name, bench(a, polys, path)))
    table(rows)
    if not a.keep:
        shutil.rmtree(tmp, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
