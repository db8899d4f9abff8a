#!/usr/bin/env python3
"""Same-run A/B of the batch benchmark: the old library (0.2.0, specialised scene kernels)
against the new one (one kernel per SIMD level and precision, law decisions at run time).

What it measures
  It builds the benchmark driver twice with the flags benches/batch.rs uses
  (cc -O3 -march=native -std=c11 -D_POSIX_C_SOURCE=199309L, the same system libraries):
    old: --old-src (default ../old/bench/bench.c, beside this checkout) with --old-include
         (../old/include) against --old-lib (../old/target/release/librollslide.a): a
         checkout of the other version, e.g. `git worktree add ../old 536037a` (0.2.0)
         and `cargo build --release --lib` in it
    new: --new-src (bench/bench.c of this repository) with --new-include (include/)
         against --new-lib (target/release/librollslide.a)
  then, for each case (workload A at --contacts contacts, A at --cache-contacts (in cache),
  B at --contacts), runs the two drivers ALTERNATELY, old, new, old, new, ... --rounds times,
  each run from a fresh copy of its binary (benches/batch.rs, fn run, explains why: a kernel's
  time depends on where the file's pages land, so a median over one file's runs reports one
  placement). Each run's number for a row is the fastest of REPS timed calls (the driver's).
  For every row both drivers print ("row GROUP NAME NS ...") it reports the median old time,
  the median new time and the median over the rounds of new/old of the same round. The C
  baselines and floors are the same code in both drivers: their ratios show the noise.

  Tables per case:
    - every row: old and new ns/contact, new/old, the kernel the old row ran (scene: a
      specialised kernel, generic: the run-time-decision kernel, from the old driver's
      "info scene_kernel" line; "-" for C code and per-contact calls) and the check the issue
      asks for: rows that ran a scene kernel must be <= 1.05x old, rows that ran the generic
      kernel must be faster than before;
    - vs old generic: each old row X[generic(Y)] (the old generic kernel forced on model Y)
      against the new row X[Y] (X alone when Y is the group's own model: full/lammps in group
      full, rolltwist, sliding);
    - new-run ratios: rolltwist and sliding batch rows over the full batch row (same precision
      and level; all three step full states), materials3/materials10 over materials1 and
      over the plain batch_f64_<l> row of group full (median over the new runs of the
      same-run ratio), with the old run's figure where it has the rows.

How to rerun it (from the repository root, after `cargo build --release --lib` here and in the
old worktree; no other heavy job running: the numbers are only as quiet as the machine):
    python3 bench/ab.py                          # full A/B, 5 rounds
    python3 bench/ab.py --rounds 7 --output ab.md
    python3 bench/ab.py --contacts 20000 --cache-contacts 2000 --rounds 1   # smoke test
  Options: --contacts N, --reps R (out-of-cache cases; defaults 1200000, 4), --cache-contacts N,
  --cache-reps R (2000, 7), --rounds N (5), --driver-arg ARG (passed to both drivers, e.g.
  --driver-arg=--slip=0.25; repeatable), --cc CC, --workdir DIR (binaries, kept), --output FILE
  (the Markdown tables also written there).

It takes a while: the default is 3 cases x 5 rounds x 2 drivers = 30 driver runs; a run at
1,200,000 contacts takes tens of seconds on a 2-core machine, so expect roughly 15-30 minutes.
Progress goes to stderr, the tables to stdout.
"""

import argparse
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CFLAGS = ["-O3", "-march=native", "-std=c11", "-D_POSIX_C_SOURCE=199309L", "-Wall", "-Wextra"]
LIBS = ["-lgcc_s", "-lutil", "-lrt", "-lpthread", "-lm", "-ldl", "-lc"]
# The old generic rows on the group's own model: generic(Y) -> the new plain row.
OWN_MODEL = {"full": "full/lammps", "rolltwist": "rolltwist", "sliding": "sliding"}
# Rows of the library's batch kernels (the rows a scene kernel ran in the old library).
BATCH_PREFIXES = ("batch_", "history_", "indexed_", "contacts_", "materials")


def parse_args():
    p = argparse.ArgumentParser(
        description="Same-run A/B of bench/bench.c: old library against new, alternating runs.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=__doc__,
    )
    p.add_argument("--old-src", default=os.path.join(ROOT, "..", "old", "bench", "bench.c"))
    p.add_argument("--old-include", default=os.path.join(ROOT, "..", "old", "include"))
    p.add_argument("--old-lib", default=os.path.join(ROOT, "..", "old", "target", "release", "librollslide.a"))
    p.add_argument("--new-src", default=os.path.join(ROOT, "bench", "bench.c"))
    p.add_argument("--new-include", default=os.path.join(ROOT, "include"))
    p.add_argument("--new-lib", default=os.path.join(ROOT, "target", "release", "librollslide.a"))
    p.add_argument("--contacts", type=int, default=1200000,
                   help="contacts of the out-of-cache cases (A and B)")
    p.add_argument("--reps", type=int, default=4, help="timed calls per row out of cache")
    p.add_argument("--cache-contacts", type=int, default=2000,
                   help="contacts of the in-cache case (A); 0 to skip it")
    p.add_argument("--cache-reps", type=int, default=7, help="timed calls per row in cache")
    p.add_argument("--rounds", type=int, default=5, help="old/new pairs of runs per case")
    p.add_argument("--driver-arg", action="append", default=[],
                   help="argument passed to both drivers (repeatable)")
    p.add_argument("--cc", default=os.environ.get("CC", "cc"))
    p.add_argument("--workdir", default=None, help="where the binaries go (default: a temp dir)")
    p.add_argument("--output", default=None, help="also write the Markdown to this file")
    a = p.parse_args()
    if a.rounds < 1 or a.contacts < 1 or a.reps < 1 or a.cache_reps < 1 or a.cache_contacts < 0:
        p.error("sizes, reps and rounds must be positive")
    return a


def log(t0, msg):
    print(f"[{time.time() - t0:7.1f} s] {msg}", file=sys.stderr, flush=True)


def build(cc, src, include, lib, out):
    for path in (src, include, lib):
        if not os.path.exists(path):
            sys.exit(f"ab.py: {path} not found (build the library with `cargo build --release "
                     f"--lib` first)")
    cmd = [cc] + CFLAGS + ["-I", include, src, lib] + LIBS + ["-o", out]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"ab.py: compiling {src} failed:\n{' '.join(cmd)}\n{r.stderr}")
    if r.stderr.strip():
        print(f"warnings compiling {src}:\n{r.stderr}", file=sys.stderr)
    return out


class Run:
    """One driver run: its info lines and rows {(group, name): (ns, loads, state, flags)}."""

    def __init__(self, text):
        self.info = []
        self.rows = {}
        self.order = []
        for line in text.splitlines():
            if line.startswith("info "):
                self.info.append(line[5:])
                continue
            f = line.split()
            if len(f) != 7 or f[0] != "row":
                raise ValueError(f"unexpected driver output: {line}")
            key = (f[1], f[2])
            self.rows[key] = (float(f[3]), f[4], f[5], f[6])
            self.order.append(key)

    def ns(self, group, name):
        r = self.rows.get((group, name))
        return r[0] if r else None

    def scene_codes(self):
        """The old driver's `info scene_kernel full=N ... generic(X)=0 (...)`: model -> code."""
        for line in self.info:
            if line.startswith("scene_kernel"):
                codes = {}
                for tok in line.split()[1:]:
                    if tok.startswith("("):
                        break
                    k, _, v = tok.rpartition("=")
                    if k:
                        codes[k] = int(v) if v.isdigit() else None
                return codes
        return {}


def run_driver(exe, workdir, tag, workload, contacts, reps, extra):
    copy = os.path.join(workdir, f"{tag}.run-{os.getpid()}-{time.time_ns()}")
    shutil.copy2(exe, copy)
    try:
        r = subprocess.run([copy, str(contacts), str(reps), f"--workload={workload}"] + extra,
                           capture_output=True, text=True)
    finally:
        os.remove(copy)
    if r.returncode != 0:
        sys.exit(f"ab.py: {tag} driver (workload {workload}, {contacts} contacts) failed "
                 f"(status {r.returncode}):\n{r.stderr}")
    return Run(r.stdout)


def med(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def fmt(x, digits=2):
    return "-" if x is None else f"{x:.{digits}f}"


def median_ratio(num_runs, num_key, den_runs, den_key):
    """Median over the rounds of num/den, run k of num_runs against run k of den_runs."""
    vals = []
    for a, b in zip(num_runs, den_runs):
        x, y = a.ns(*num_key), b.ns(*den_key)
        if x is not None and y is not None and y > 0:
            vals.append(x / y)
    return med(vals)


def old_kernel(name, group, codes):
    """The kernel an old row ran: scene, generic, or "-" (not a batch kernel)."""
    if not name.startswith(BATCH_PREFIXES) or not codes:
        return "-"
    model = group
    if "[" in name:
        inner = name[name.index("[") + 1:].rstrip("]")
        if inner != "noslip":
            model = inner
    code = codes.get(model)
    if code is None:
        return "?"
    return "generic" if code == 0 else "scene"


def check(kernel, ratio):
    if ratio is None:
        return ""
    if kernel == "scene":
        return "ok (<= 1.05)" if ratio <= 1.05 else "**> 1.05**"
    if kernel == "generic":
        return "ok (faster)" if ratio < 1.0 else "**not faster**"
    return ""


def generic_target(name, group, new_names):
    """The new row an old X[generic(Y)] row is set against, or None."""
    i = name.find("[generic(")
    if i < 0 or not name.endswith(")]"):
        return None
    x, y = name[:i], name[i + len("[generic("):-2]
    if f"{x}[{y}]" in new_names:
        return f"{x}[{y}]"
    if OWN_MODEL.get(group) == y and x in new_names:
        return x
    return None


def case_tables(title, old_runs, new_runs):
    md = [f"\n## {title} ({len(new_runs)} round(s))\n"]
    old0, new0 = old_runs[0], new_runs[0]
    codes = old0.scene_codes()
    new_keys = set(new0.rows)
    md.append("New run's info:\n")
    md += [f"- {line}" for line in new0.info]
    md.append("\nOld run's info:\n")
    md += [f"- {line}" for line in old0.info]

    md.append("\n### Every row: new / old (median of the per-round ratios)\n")
    md.append("| group | row | old ns | new ns | new/old | old kernel | check "
              "| new diff loads / state / flags |")
    md.append("|---|---|---:|---:|---:|---|---|---|")
    keys = list(new0.order) + [k for k in old0.order
                               if k not in new_keys and "[generic(" not in k[1]]
    for g, n in keys:
        o = med(r.ns(g, n) for r in old_runs)
        nw = med(r.ns(g, n) for r in new_runs)
        ratio = median_ratio(new_runs, (g, n), old_runs, (g, n))
        kern = old_kernel(n, g, codes) if (g, n) in old0.rows else "-"
        diff = new0.rows.get((g, n))
        diff = " / ".join(diff[1:]) if diff else "-"
        md.append(f"| {g} | {n} | {fmt(o)} | {fmt(nw)} | {fmt(ratio, 3)} | {kern} "
                  f"| {check(kern, ratio)} | {diff} |")

    md.append("\n### vs old generic: old X[generic(Y)] (the old generic kernel on model Y) "
              "against new X[Y]\n")
    md.append("| group | old row | new row | old generic ns | new ns | new/old generic | check |")
    md.append("|---|---|---|---:|---:|---:|---|")
    new_names = {}
    for g, n in new0.order:
        new_names.setdefault(g, set()).add(n)
    if not any("[generic(" in n for _, n in old0.order):
        md.append("| (none: the old driver runs its generic rows on workload A only) "
                  "| | | | | | |")
    for g, n in old0.order:
        if "[generic(" not in n:
            continue
        target = generic_target(n, g, new_names.get(g, set()))
        o = med(r.ns(g, n) for r in old_runs)
        if target is None:
            md.append(f"| {g} | {n} | (none) | {fmt(o)} | - | - | |")
            continue
        nw = med(r.ns(g, target) for r in new_runs)
        ratio = median_ratio(new_runs, (g, target), old_runs, (g, n))
        md.append(f"| {g} | {n} | {target} | {fmt(o)} | {fmt(nw)} | {fmt(ratio, 3)} "
                  f"| {check('generic', ratio)} |")

    md.append("\n### New run's same-run ratios (median over the rounds; old run's where it "
              "has the rows)\n")
    md.append("| ratio | new | old |")
    md.append("|---|---:|---:|")
    levels = [n[len("batch_f64_"):] for g, n in new0.order
              if g == "full" and n.startswith("batch_f64_") and "[" not in n]
    levels32 = [n[len("batch_f32_"):] for g, n in new0.order
                if g == "full" and n.startswith("batch_f32_") and "[" not in n]

    def same_run(runs, num, den):
        return med([r.ns(*num) / r.ns(*den) for r in runs
                    if r.ns(*num) is not None and r.ns(*den)])

    lines = []
    for p, lvls in (("f64", levels), ("f32", levels32)):
        for lv in lvls:
            full = ("full", f"batch_{p}_{lv}")
            for g in ("rolltwist", "sliding"):
                num = (g, f"batch_{p}_{lv}")
                lines.append((f"{g} batch_{p}_{lv} / full batch_{p}_{lv}", num, full))
    for lv in levels:
        plain = ("full", f"batch_f64_{lv}")
        m1 = ("full", f"materials1_f64_{lv}")
        lines.append((f"materials1_f64_{lv} / batch_f64_{lv}", m1, plain))
        for n in (3, 10):
            mn = ("full", f"materials{n}_f64_{lv}")
            lines.append((f"materials{n}_f64_{lv} / materials1_f64_{lv}", mn, m1))
            lines.append((f"materials{n}_f64_{lv} / batch_f64_{lv}", mn, plain))
    for label, num, den in lines:
        md.append(f"| {label} | {fmt(same_run(new_runs, num, den), 3)} "
                  f"| {fmt(same_run(old_runs, num, den), 3)} |")
    return "\n".join(md) + "\n"


def git_head(path):
    try:
        r = subprocess.run(["git", "-C", path, "rev-parse", "--short", "HEAD"],
                           capture_output=True, text=True)
        return r.stdout.strip() or "?"
    except OSError:
        return "?"


def machine():
    cpu = "?"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        with open("/sys/kernel/mm/transparent_hugepage/enabled") as f:
            t = f.read()
            thp = t[t.index("[") + 1:t.index("]")]
    except (OSError, ValueError):
        thp = "unknown"
    return cpu, thp


def loadavg():
    try:
        with open("/proc/loadavg") as f:
            return " ".join(f.read().split()[:3])
    except OSError:
        return "?"


def main():
    a = parse_args()
    t0 = time.time()
    workdir = a.workdir or tempfile.mkdtemp(prefix="rsl-ab-")
    os.makedirs(workdir, exist_ok=True)
    log(t0, f"building the drivers in {workdir}")
    old_exe = build(a.cc, a.old_src, a.old_include, a.old_lib, os.path.join(workdir, "old_driver"))
    new_exe = build(a.cc, a.new_src, a.new_include, a.new_lib, os.path.join(workdir, "new_driver"))

    cases = [("A", a.contacts, a.reps)]
    if a.cache_contacts:
        cases.append(("A", a.cache_contacts, a.cache_reps))
    cases.append(("B", a.contacts, a.reps))
    load_start = loadavg()
    results = []
    for w, n, reps in cases:
        old_runs, new_runs = [], []
        for r in range(a.rounds):
            log(t0, f"workload {w}, {n} contacts, round {r + 1}/{a.rounds}: old")
            old_runs.append(run_driver(old_exe, workdir, "old", w, n, reps, a.driver_arg))
            log(t0, f"workload {w}, {n} contacts, round {r + 1}/{a.rounds}: new")
            new_runs.append(run_driver(new_exe, workdir, "new", w, n, reps, a.driver_arg))
        results.append((f"Workload {w}, {n} contacts, {reps} calls per row", old_runs, new_runs))
    elapsed = time.time() - t0
    if not a.workdir:
        shutil.rmtree(workdir, ignore_errors=True)

    cpu, thp = machine()
    md = ["# rollslide batch benchmark: same-run A/B, old against new\n",
          f"CPU: {cpu} ({platform.machine()}); transparent huge pages: {thp}; GLIBC_TUNABLES: "
          f"{os.environ.get('GLIBC_TUNABLES', 'unset')}. Load average (1, 5, 15 min): "
          f"{load_start} at the start, {loadavg()} at the end; {elapsed:.0f} s in all.\n",
          f"- old: {a.old_src} (commit {git_head(os.path.dirname(a.old_src))}), "
          f"-I {a.old_include}, {a.old_lib}",
          f"- new: {a.new_src} (commit {git_head(os.path.dirname(a.new_src))} + working tree), "
          f"-I {a.new_include}, {a.new_lib}",
          f"- {a.rounds} round(s) per case, each old then new, each run from a fresh copy of its "
          f"binary; driver arguments: {' '.join(a.driver_arg) or '(none)'}",
          "- ns: ns per contact, median over the rounds of each run's fastest call; new/old: "
          "median over the rounds of the same round's ratio. The baseline_c* and floor* rows "
          "are the same C code in both drivers: their ratios show the noise.",
          "- check: rows whose old model ran a specialised scene kernel must be <= 1.05x old; "
          "rows that ran the old generic kernel must be faster (also the \"vs old generic\" "
          "table)."]
    for title, old_runs, new_runs in results:
        md.append(case_tables(title, old_runs, new_runs))
    text = "\n".join(md)
    print(text)
    if a.output:
        with open(a.output, "w") as f:
            f.write(text)
        print(f"written to {a.output}", file=sys.stderr)


if __name__ == "__main__":
    main()
