#!/usr/bin/env python3
"""Measures how `skinpath check --dialect linuxcnc` agrees with LinuxCNC on a folder of
G-code programs (issue #42: "programs from other tools that LinuxCNC refuses for a reason in
the program get an error from check in at least 90 % of cases").

Fetches nothing: give it a local folder of programs (.nc .ngc .gcode .tap .cnc, searched
recursively). For each program:

1. LinuxCNC's verdict: `skinpath check --backend linuxcnc --json` runs rs274 (package
   linuxcnc-uspace) with the tool table and subroutine path skinpath uses; its refusals are
   the `canon-error` findings ("rs274: <LinuxCNC's message> (in `<block>`)"). A refusal is
   sorted by its message (REASONS below): tool table, subroutine file, machine
   configuration, or else the program itself.
2. skinpath's verdict: `skinpath check --dialect linuxcnc --json` (built-in interpreter):
   does it give an error finding, and one on the line rs274 refused?

Prints the table (files, readable, refused by reason, program refusals caught, accepted
programs with errors) and, with --details, one line per program. --rs274-cache FILE keeps
rs274's verdicts between runs (rs274 is the slow half; the verdict depends only on the
file's contents, keyed by their SHA-256).

Usage: scripts/refusal_corpus.py FOLDER [--skinpath target/release/skinpath] [--jobs 2]
       [--rs274-cache FILE] [--details FILE.tsv]
"""

import argparse
import concurrent.futures
import hashlib
import json
import os
import re
import subprocess
import sys

EXTENSIONS = (".nc", ".ngc", ".gcode", ".tap", ".cnc")

# rs274 refusals that are not about the program: (reason, pattern of LinuxCNC's message).
# Messages are LinuxCNC's (src/emc/rs274ngc/rs274ngc_return.hh, interp_*.cc).
REASONS = [
    ("tool table", re.compile(
        r"tool (number|slot)|pocket|toolchange|Tool .* not found|selected tool|tool table",
        re.I)),
    ("subroutine file", re.compile(
        r"Unable to open file|Unknown oword|file not open|not in (a )?sub|"
        r"Subroutine .* not found|Unable to (find|open) .*\.ngc|named file",
        re.I)),
    # User M-codes (M100-M199) are programs in the machine's folder; #<_hal[...]>,
    # #<_ini[...]> and Python parameters come from its HAL, INI and Python set-up.
    ("machine config", re.compile(
        r"remap|\bINI\b|axis .* not (configured|exist)|Unknown M code used|user.defined M|"
        r"Python|#<_py|#<_hal\[|#<_ini\[|machine limit|soft limit",
        re.I)),
]

# rs274 reads at most LINELEN - 1 = 254 bytes of a line, newline included (linuxcnc.h
# LINELEN 255, interp_read.cc read_text): a longer line is NCE_COMMAND_TOO_LONG. skinpath's
# backend prefixes every line with `N<line> ` to keep line numbers, so a line within the limit
# in the file can pass it in the run: such a refusal is the measurement's, not LinuxCNC's.
LINUXCNC_MAX_LINE = 253
NUMBERING = "numbering artefact"

CANON_ERROR = re.compile(r"^rs274: (.*?)(?: \(in `.*`\))?$", re.S)


def check(skinpath, path, backend, timeout):
    """`skinpath check` report as JSON, or None when it gave none (crash, no output)."""
    cmd = [skinpath, "check", "--dialect", "linuxcnc", "--json", path]
    if backend == "linuxcnc":
        cmd[2:2] = ["--backend", "linuxcnc", "--rs274-timeout", str(timeout)]
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, errors="replace",
                             timeout=timeout * 30)
    except subprocess.TimeoutExpired:
        return None
    try:
        return json.loads(out.stdout)
    except json.JSONDecodeError:
        return None


def reason_of(message):
    for reason, pattern in REASONS:
        if pattern.search(message):
            return reason
    return "program"


def rs274_verdict(skinpath, path, timeout):
    """(state, reason, message, lines): state is readable / unreadable (no reading)."""
    rep = check(skinpath, path, "linuxcnc", timeout)
    if rep is None or not rep.get("usable", False):
        msg = ""
        if rep:
            msg = "; ".join(f["message"] for f in rep["findings"] if f["severity"] == "error")
        return ("unreadable", "", msg[:200], [])
    errs = [f for f in rep["findings"] if f["id"] == "canon-error"]
    if not errs:
        return ("accepted", "", "", [])
    m = CANON_ERROR.match(errs[0]["message"])
    msg = (m.group(1) if m else errs[0]["message"]).strip()
    return ("refused", "", msg[:200], errs[0].get("lines", []))


def classify(path, verdict):
    """The verdict with the reason of a refusal filled in (from its message and the file)."""
    state, _, msg, lines = verdict
    if state != "refused":
        return verdict
    reason = reason_of(msg)
    if msg.startswith("Command too long") and lines:
        with open(path, "rb") as f:
            raw = f.read().split(b"\n")
        if all(len(raw[n - 1].rstrip(b"\r")) < LINUXCNC_MAX_LINE for n in lines if n <= len(raw)):
            reason = NUMBERING
    return [state, reason, msg, lines]


# Findings about the geometry and the machine profile, not about reading the program: an
# error of these kinds is not counted as catching a refusal (it would catch it by chance).
GEOMETRY = {"out-of-bounds", "power-out-of-range", "feed-out-of-range", "self-intersection",
            "contour-crossing", "tool-on-at-end", "laser-on-rapid", "rapid-below-safe-z",
            "rapid-into-stock", "gouge"}


def builtin_verdict(skinpath, path, timeout):
    """(errors: [(id, lines)]) of the built-in check, or None when it gave no report."""
    rep = check(skinpath, path, "builtin", timeout)
    if rep is None:
        return None
    return [(f["id"], f.get("lines", [])) for f in rep["findings"] if f["severity"] == "error"]


def sha(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folder")
    ap.add_argument("--skinpath", default="target/release/skinpath")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=10.0,
                    help="rs274 processor-time limit per program (s)")
    ap.add_argument("--rs274-cache")
    ap.add_argument("--details")
    args = ap.parse_args()

    files = sorted(
        os.path.join(d, n)
        for d, _, names in os.walk(args.folder)
        for n in names
        if n.lower().endswith(EXTENSIONS)
    )
    cache = {}
    if args.rs274_cache and os.path.exists(args.rs274_cache):
        with open(args.rs274_cache) as f:
            cache = json.load(f)

    def one(path):
        key = sha(path)
        verdict = cache.get(key)
        if verdict is None:
            verdict = list(rs274_verdict(args.skinpath, path, args.timeout))
        return path, key, classify(path, verdict), builtin_verdict(args.skinpath, path,
                                                                    args.timeout)

    rows = []
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        for path, key, verdict, errors in pool.map(one, files):
            cache[key] = verdict
            rows.append((path, verdict, errors))

    if args.rs274_cache:
        with open(args.rs274_cache, "w") as f:
            json.dump(cache, f)

    count = {}
    caught = caught_line = caught_reading = accepted_err = accepted_reading = accepted = 0
    detail_lines = []
    for path, (state, reason, msg, lines), errors in rows:
        key = reason if state == "refused" else state
        count[key] = count.get(key, 0) + 1
        errors = errors or []
        ids = ",".join(sorted({i for i, _ in errors}))
        if state == "refused" and reason == "program":
            if errors:
                caught += 1
            if any(i not in GEOMETRY for i, _ in errors):
                caught_reading += 1
            if any(set(ls) & set(lines) for _, ls in errors):
                caught_line += 1
        if state == "accepted":
            accepted += 1
            if errors:
                accepted_err += 1
            if any(i not in GEOMETRY for i, _ in errors):
                accepted_reading += 1
        detail_lines.append("\t".join([os.path.relpath(path, args.folder), state, reason,
                                       ids, msg.replace("\t", " ").replace("\n", " ")]))
    if args.details:
        with open(args.details, "w") as f:
            f.write("file\trs274\treason\tcheck errors\trs274 message\n")
            f.write("\n".join(detail_lines) + "\n")

    total = len(rows)
    readable = total - count.get("unreadable", 0)
    refused = sum(v for k, v in count.items() if k not in ("accepted", "unreadable"))
    program = count.get("program", 0)
    pct = lambda a, b: f"{100.0 * a / b:.1f} %" if b else "-"
    print(f"files                          {total}")
    print(f"readable by rs274              {readable}")
    print(f"accepted by rs274              {accepted}")
    print(f"refused by rs274               {refused}")
    for r in ("tool table", "subroutine file", "machine config", NUMBERING, "program"):
        print(f"  {r:<28} {count.get(r, 0)}")
    print(f"program refusals with a check error          {caught} / {program} ({pct(caught, program)})")
    print(f"  ... a reading error (not geometry/limits)  {caught_reading} / {program} ({pct(caught_reading, program)})")
    print(f"  ... an error on the refused line           {caught_line} / {program} ({pct(caught_line, program)})")
    print(f"accepted programs with a check error         {accepted_err} / {accepted} ({pct(accepted_err, accepted)})")
    print(f"  ... a reading error (not geometry/limits)  {accepted_reading} / {accepted} ({pct(accepted_reading, accepted)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
