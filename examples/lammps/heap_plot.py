#!/usr/bin/env python3
"""Dissipation by mechanism, and the angle of repose, against a parameter of the heap, from the
logs of examples/lammps/heap.sh.

    python3 heap_plot.py OUT.svg LOG [LOG ...]

Each LOG is a run of examples/lammps/inputs/in.heap named `log.<parameter>-<value>` (mu_r or
coh), as heap.sh names them; the final positions, when in.heap wrote them, are in
`dump.<parameter>-<value>` beside it. The last thermo row holds `compute rollslide/energy`'s
vector c_e[1..]: the dissipation since the pour started, by mechanism, for pair and wall
contacts. Writes a stacked-bar SVG (each bar the whole dissipation of one heap, split by mode:
normal damping, sliding, rolling, twisting, and JKR's neck breaking where any neck broke; pair
and wall contacts together; a coh sweep adds a panel with the angle of repose) and prints
Markdown tables on standard output: the modes' totals (percent of the total), the wall
contacts' share, the total, the kinetic energy left and the angle of repose; then each mode's
dashpot and friction apart. A mode's total below -1e-9 of the dissipated energy (pair or wall
contacts, or both) is flagged on standard error (`heap_plot: warning`; a negative neck-breaking
value: `heap_plot: note`), which also gets the smallest nonzero mode total seen. Plain python3.

The angle of repose: the spheres' tops (z + radius) in cells of radial bins 1 wide around the
pour axis (x = y = 0) and azimuthal sectors about 2 long; a cell's surface is its highest top,
a bin's the median over its sectors (an empty cell counts 0); the heap's edge is the first bin
outward from the highest one whose surface is below 1.5 (one layer of spheres on the floor), at
radius R; the angle is the arctangent of the slope of a least-squares line through the bins'
surfaces between 0.2 R and 0.8 R (bin centres). Spheres that spread into a carpet (no bin's
surface above 2.5: two layers at most) have none: `none` in the table.
"""
import math
import os
import re
import statistics
import sys

# By mode: the normal dashpot, then the sliding, rolling and twisting springs' dashpot and
# slider together (the compute's columns 1-7 for pair contacts, 8-14 for wall contacts: normal
# damping, then dashpot and friction of each mode). Together, because the split between a
# mode's dashpot and its slider is not a split of the dissipation while the contact slips: the
# clip keeps the dashpot inside the Coulomb limit and resets the spring, so the spring can take
# back part of what the dashpot term counts, and the friction entry then goes negative; their
# sum is what the mode dissipated.
MECHANISMS = [
    ("normal damping", "#4c72b0", [0]),
    ("sliding", "#dd8452", [1, 2]),
    ("rolling", "#55a868", [3, 4]),
    ("twisting", "#8172b3", [5, 6]),
]
# JKR's necks that broke at pull-off (c_e[38] pair, c_e[39] wall); shown where any neck broke.
NECKS = ("neck breaking", "#c44e52", None)
SPLIT = [("sliding", 1, 2), ("rolling", 3, 4), ("twisting", 5, 6)]


def columns(t, mechanism):
    """A mechanism's (pair, wall) dissipation from the thermo row t."""
    name, _, cols = mechanism
    if cols is None:
        return t.get("c_e[38]", 0.0), t.get("c_e[39]", 0.0)
    return (sum(t[f"c_e[{k + 1}]"] for k in cols), sum(t[f"c_e[{k + 8}]"] for k in cols))


def last_thermo(path):
    """The header and the last numeric row of the last thermo block of a LAMMPS log."""
    header, row = None, None
    with open(path) as f:
        for line in f:
            words = line.split()
            if words[:1] == ["Step"]:
                header = words
                continue
            if header and len(words) == len(header):
                try:
                    row = [float(w) for w in words]
                except ValueError:
                    pass
    if header is None or row is None:
        sys.exit(f"heap_plot: no thermo rows in {path}")
    return dict(zip(header, row))


def percent(part, total):
    """`part` as a percentage of `total`, one decimal (a rounding -0.0 shown as 0.0)."""
    return f"{100 * part / total + 0.0:.1f} %".replace("-0.0 %", "0.0 %")


def parameter_of(path):
    m = re.search(r"log\.([a-z_]+)-([0-9.eE+-]+?)(?:\.log)?$", os.path.basename(path))
    if not m:
        sys.exit(f"heap_plot: cannot read the parameter from the file name {path} "
                 "(log.<parameter>-<value>)")
    return m.group(1), float(m.group(2))


def law_of(path):
    """The normal model of the run's pair_coeff (its first word), as the log echoes it once its
    variables are substituted."""
    law = "?"
    with open(path) as f:
        for line in f:
            words = line.split()
            if words[:3] == ["pair_coeff", "*", "*"] and len(words) > 3 and "$" not in words[3]:
                law = words[3]
    return law


def angle_of_repose(path):
    """The heap's angle of repose in degrees from a write_dump of id x y z radius (module
    docstring), or None without the file or a heap to fit."""
    if not os.path.exists(path):
        return None
    with open(path) as f:
        lines = f.read().split("\n")
    start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
    cells = {}
    for line in lines[start:]:
        words = line.split()
        if len(words) < 5:
            continue
        x, y, z, radius = (float(w) for w in words[1:5])
        r = math.hypot(x, y)
        b = int(r)
        sectors = max(1, round(2 * math.pi * (b + 0.5) / 2))
        s = int((math.atan2(y, x) + math.pi) / (2 * math.pi) * sectors) % sectors
        cells[(b, s)] = max(cells.get((b, s), 0.0), z + radius)
    bins = max(b for b, _ in cells) + 1
    surface = []
    for b in range(bins):
        sectors = max(1, round(2 * math.pi * (b + 0.5) / 2))
        surface.append(statistics.median(cells.get((b, s), 0.0) for s in range(sectors)))
    peak = max(range(bins), key=lambda b: surface[b])
    if surface[peak] < 2.5:
        return None  # no more than two layers of spheres anywhere: no heap
    edge = next((b for b in range(peak, bins) if surface[b] < 1.5), bins)
    points = [(b + 0.5, surface[b]) for b in range(edge) if 0.2 * edge <= b + 0.5 <= 0.8 * edge]
    if len(points) < 3:
        return None
    mx = sum(p for p, _ in points) / len(points)
    my = sum(h for _, h in points) / len(points)
    slope = (sum((p - mx) * (h - my) for p, h in points)
             / sum((p - mx) ** 2 for p, _ in points))
    return math.degrees(math.atan(-slope))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out, logs = sys.argv[1], sys.argv[2:]
    rows = []
    for path in logs:
        param, value = parameter_of(path)
        dump = os.path.join(os.path.dirname(path),
                            "dump." + os.path.basename(path)[len("log."):])
        rows.append((value, param, last_thermo(path), law_of(path), angle_of_repose(dump)))
    rows.sort(key=lambda r: r[0])
    param = rows[0][1]
    if any(r[1] != param for r in rows):
        sys.exit("heap_plot: the logs sweep different parameters")
    necks = any(t.get("c_e[38]", 0.0) != 0.0 or t.get("c_e[39]", 0.0) != 0.0
                for _, _, t, _, _ in rows)
    mechanisms = MECHANISMS + [NECKS] if necks else MECHANISMS
    runs = []
    smallest = None
    for value, _, t, law, angle in rows:
        pair = [columns(t, m)[0] for m in mechanisms]
        wall = [columns(t, m)[1] for m in mechanisms]
        total = sum(pair) + sum(wall)
        kinetic = t.get("KinEng", float("nan")) + t.get("c_rot", 0.0)
        runs.append((value, pair, wall, total, kinetic, int(t["Atoms"]), angle, t))
        # A mode's total (dashpot and friction) is what it dissipated: never negative beyond
        # rounding, for the pair and the wall contacts apart and together. The necks' value is
        # no dashpot or slider: a neck found broken after a step that left it bound (U < 0, a
        # fast rebound crossing the neck's stretch in one step) counts a negative U.
        for (name, _, cols), p, w in zip(mechanisms, pair, wall):
            for what, e in (("pair", p), ("wall", w), ("pair and wall", p + w)):
                if cols is not None and e != 0.0 and (smallest is None
                                                      or e / total < smallest[0]):
                    smallest = (e / total, name, what, value)
                if e < -1e-9 * total:
                    kind = "warning" if cols is not None else "note"
                    print(f"heap_plot: {kind}: {param} {value:g}: {name} ({what} contacts) "
                          f"{e:.6g}, {e / total:.3g} of the dissipated energy", file=sys.stderr)
    if smallest is not None:
        print(f"heap_plot: smallest mode total (dashpot and friction, nonzero): {smallest[0]:.3g}"
              f" of the dissipated energy ({smallest[1]}, {smallest[2]} contacts, {param} "
              f"{smallest[3]:g})", file=sys.stderr)
    laws = {r[3] for r in rows}
    law = laws.pop() if len(laws) == 1 else "?"

    # The table: the modes' totals.
    names = [m for m, _, _ in mechanisms]
    print(f"| {param} | angle of repose | " + " | ".join(names)
          + " | of which wall contacts | total dissipated | kinetic left |")
    print("|---:|---:|" + "---:|" * (len(names) + 3))
    for value, pair, wall, total, kinetic, _, angle, _ in runs:
        shares = [percent(p + w, total) for p, w in zip(pair, wall)]
        degrees = "none" if angle is None else f"{angle:.1f}°"
        print(f"| {value:g} | {degrees} | " + " | ".join(shares)
              + f" | {percent(sum(wall), total)} | {total:.1f} | {kinetic:.2e} |")
    # Each mode's dashpot and friction apart (pair and wall contacts together): not a split of
    # the dissipation where LAMMPS' clip rule acts (a friction entry can be negative).
    print()
    print(f"| {param} | " + " | ".join(f"{m} dashpot | {m} friction" for m, _, _ in SPLIT)
          + " |")
    print("|---:|" + "---:|" * (2 * len(SPLIT)))
    for value, _, _, total, _, _, _, t in runs:
        cells = []
        for _, d, fr in SPLIT:
            for k in (d, fr):
                cells.append(percent(t[f"c_e[{k + 1}]"] + t[f"c_e[{k + 8}]"], total))
        print(f"| {value:g} | " + " | ".join(cells) + " |")

    # The plot: one stacked bar per value, fractions of the heap's total dissipation; a coh
    # sweep adds the angle of repose on a panel to the right.
    angles = param != "mu_r"
    width, height = (760 + 330 if angles else 760), 420
    left, right, top, bottom = 70, 190 + (330 if angles else 0), 40, 60
    plot_w, plot_h = width - left - right, height - top - bottom
    n = len(runs)
    slot = plot_w / n
    bar = slot * 0.6
    label = {"hertz/material": "Hertz-Mindlin", "jkr": "JKR"}.get(law, law)
    title = ("Where a poured heap\'s energy went, by mechanism" if law == "hooke"
             else f"Where a poured heap\'s energy went, {label}")
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'font-family="sans-serif" font-size="12">',
           f'<rect width="{width}" height="{height}" fill="white"/>',
           f'<text x="{left}" y="22" font-size="14">{title} ({runs[0][5]} spheres, '
           f'in.heap)</text>']
    for k in range(0, 101, 20):
        y = top + plot_h * (1 - k / 100)
        svg.append(f'<line x1="{left}" x2="{left + plot_w}" y1="{y:.1f}" y2="{y:.1f}" '
                   f'stroke="#ddd"/>')
        svg.append(f'<text x="{left - 8}" y="{y + 4:.1f}" text-anchor="end">{k} %</text>')
    for i, (value, pair, wall, total, _, _, _, _) in enumerate(runs):
        x = left + slot * i + (slot - bar) / 2
        y = top + plot_h
        for (name, colour, _), p, w in zip(mechanisms, pair, wall):
            # A mode's total is never negative beyond rounding (checked above); a rounding
            # below zero draws nothing.
            h = plot_h * max(p + w, 0.0) / total
            y -= h
            svg.append(f'<rect x="{x:.1f}" y="{y:.1f}" width="{bar:.1f}" height="{h:.1f}" '
                       f'fill="{colour}"><title>{param} {value:g}: {name} '
                       f'{100 * (p + w) / total:.1f} %</title></rect>')
            if h >= 14:
                svg.append(f'<text x="{x + bar / 2:.1f}" y="{y + h / 2 + 4:.1f}" '
                           f'text-anchor="middle" fill="white">{percent(p + w, total)}</text>')
        svg.append(f'<text x="{x + bar / 2:.1f}" y="{top + plot_h + 18}" '
                   f'text-anchor="middle">{value:g}</text>')
    axis = {"mu_r": "rolling friction coefficient mu_r",
            "coh": "surface energy density coh"}.get(param, param)
    svg.append(f'<text x="{left + plot_w / 2}" y="{height - 18}" text-anchor="middle">'
               f'{axis}</text>')
    svg.append(f'<text x="18" y="{top + plot_h / 2}" text-anchor="middle" '
               f'transform="rotate(-90 18 {top + plot_h / 2})">share of the energy dissipated</text>')
    for k, (name, colour, _) in enumerate(reversed(mechanisms)):
        y = top + 10 + 22 * k
        svg.append(f'<rect x="{left + plot_w + 20}" y="{y}" width="14" height="14" '
                   f'fill="{colour}"/>')
        svg.append(f'<text x="{left + plot_w + 40}" y="{y + 11}">{name}</text>')
    if angles:
        svg += angle_panel(runs, left + plot_w + 190, top, 260, plot_h, axis)
    svg.append("</svg>")
    with open(out, "w") as f:
        f.write("\n".join(svg) + "\n")


def angle_panel(runs, x0, top, w, h, axis):
    """The angle of repose against the swept value: an SVG panel at (x0, top), w by h; a run
    whose spheres made no heap is an open circle at 0, labelled `none`."""
    values = [r[0] for r in runs]
    points = [(r[0], r[6]) for r in runs if r[6] is not None]
    xmax = max(values) or 1.0
    amax = 10 * math.ceil(max((a for _, a in points), default=10.0) / 10 + 0.01)
    svg = [f'<text x="{x0}" y="{top - 8}">angle of repose</text>']
    for k in range(0, int(amax) + 1, 10):
        y = top + h * (1 - k / amax)
        svg.append(f'<line x1="{x0}" x2="{x0 + w}" y1="{y:.1f}" y2="{y:.1f}" stroke="#ddd"/>')
        svg.append(f'<text x="{x0 - 6}" y="{y + 4:.1f}" text-anchor="end">{k}°</text>')
    for v in values:
        x = x0 + 14 + (w - 14) * v / xmax
        svg.append(f'<text x="{x:.1f}" y="{top + h + 18}" text-anchor="middle">{v:g}</text>')
    xy = [(x0 + 14 + (w - 14) * v / xmax, top + h * (1 - a / amax)) for v, a in points]
    svg.append('<polyline fill="none" stroke="#333" stroke-width="1.5" points="'
               + " ".join(f"{x:.1f},{y:.1f}" for x, y in xy) + '"/>')
    for (v, a), (x, y) in zip(points, xy):
        svg.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="4" fill="#333"><title>{v:g}: '
                   f'{a:.1f}°</title></circle>')
        svg.append(f'<text x="{x:.1f}" y="{y - 9:.1f}" text-anchor="middle">{a:.0f}°</text>')
    for r in runs:
        if r[6] is None:
            x = x0 + 14 + (w - 14) * r[0] / xmax
            svg.append(f'<circle cx="{x:.1f}" cy="{top + h}" r="4" fill="white" stroke="#333">'
                       f'<title>{r[0]:g}: no heap</title></circle>')
            svg.append(f'<text x="{x:.1f}" y="{top + h - 9}" text-anchor="middle">none</text>')
    svg.append(f'<text x="{x0 + w / 2}" y="{top + h + 42}" text-anchor="middle">{axis}</text>')
    return svg


if __name__ == "__main__":
    main()
