#!/usr/bin/env python3
"""Dissipation by mechanism against rolling friction, from the logs of examples/lammps/heap.sh.

    python3 heap_plot.py OUT.svg LOG [LOG ...]

Each LOG is a run of examples/lammps/inputs/in.heap named `log.mu_r-<value>`, as heap.sh
names them. The last thermo row holds `compute rollslide/energy`'s vector c_e[1..]: the
dissipation since the pour started, by mechanism, for pair and wall contacts. Writes a
stacked-bar SVG (each bar the whole dissipation of one heap, split by mode: normal damping,
sliding, rolling, twisting; pair and wall contacts together) and prints a Markdown table
(percent of the total, the wall contacts' share, the total, and the kinetic energy left) on
standard output. Plain python3.
"""
import re
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


def mu_r_of(path):
    m = re.search(r"mu_r-([0-9.eE+-]+?)(?:\.log)?$", path)
    if not m:
        sys.exit(f"heap_plot: cannot read mu_r from the file name {path} (log.mu_r-<value>)")
    return float(m.group(1))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out, logs = sys.argv[1], sys.argv[2:]
    runs = []
    for path in logs:
        t = last_thermo(path)
        pair = [sum(t[f"c_e[{k + 1}]"] for k in cols) for _, _, cols in MECHANISMS]
        wall = [sum(t[f"c_e[{k + 8}]"] for k in cols) for _, _, cols in MECHANISMS]
        total = sum(pair) + sum(wall)
        kinetic = t.get("KinEng", float("nan")) + t.get("c_rot", 0.0)
        runs.append((mu_r_of(path), pair, wall, total, kinetic, int(t["Atoms"])))
    runs.sort()

    # The table.
    names = [m for m, _, _ in MECHANISMS]
    print("| mu_r | " + " | ".join(names) + " | of which wall contacts | total dissipated | kinetic left |")
    print("|---:|" + "---:|" * (len(names) + 3))
    for mu_r, pair, wall, total, kinetic, _ in runs:
        shares = [percent(p + w, total) for p, w in zip(pair, wall)]
        print(f"| {mu_r:g} | " + " | ".join(shares)
              + f" | {percent(sum(wall), total)} | {total:.1f} | {kinetic:.2e} |")

    # The plot: one stacked bar per mu_r, fractions of the heap's total dissipation.
    width, height = 760, 420
    left, right, top, bottom = 70, 190, 40, 60
    plot_w, plot_h = width - left - right, height - top - bottom
    n = len(runs)
    slot = plot_w / n
    bar = slot * 0.6
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'font-family="sans-serif" font-size="12">',
           f'<rect width="{width}" height="{height}" fill="white"/>',
           f'<text x="{left}" y="22" font-size="14">Where a poured heap\'s energy went, by '
           f'mechanism ({runs[0][5]} spheres, in.heap)</text>']
    for k in range(0, 101, 20):
        y = top + plot_h * (1 - k / 100)
        svg.append(f'<line x1="{left}" x2="{left + plot_w}" y1="{y:.1f}" y2="{y:.1f}" '
                   f'stroke="#ddd"/>')
        svg.append(f'<text x="{left - 8}" y="{y + 4:.1f}" text-anchor="end">{k} %</text>')
    for i, (mu_r, pair, wall, total, _, _) in enumerate(runs):
        x = left + slot * i + (slot - bar) / 2
        y = top + plot_h
        for (name, colour, _), p, w in zip(MECHANISMS, pair, wall):
            h = plot_h * (p + w) / total
            y -= h
            svg.append(f'<rect x="{x:.1f}" y="{y:.1f}" width="{bar:.1f}" height="{h:.1f}" '
                       f'fill="{colour}"><title>mu_r {mu_r:g}: {name} '
                       f'{100 * (p + w) / total:.1f} %</title></rect>')
            if h >= 14:
                svg.append(f'<text x="{x + bar / 2:.1f}" y="{y + h / 2 + 4:.1f}" '
                           f'text-anchor="middle" fill="white">{percent(p + w, total)}</text>')
        svg.append(f'<text x="{x + bar / 2:.1f}" y="{top + plot_h + 18}" '
                   f'text-anchor="middle">{mu_r:g}</text>')
    svg.append(f'<text x="{left + plot_w / 2}" y="{height - 18}" text-anchor="middle">'
               f'rolling friction coefficient mu_r</text>')
    svg.append(f'<text x="18" y="{top + plot_h / 2}" text-anchor="middle" '
               f'transform="rotate(-90 18 {top + plot_h / 2})">share of the energy dissipated</text>')
    for k, (name, colour, _) in enumerate(reversed(MECHANISMS)):
        y = top + 10 + 22 * k
        svg.append(f'<rect x="{left + plot_w + 20}" y="{y}" width="14" height="14" '
                   f'fill="{colour}"/>')
        svg.append(f'<text x="{left + plot_w + 40}" y="{y + 11}">{name}</text>')
    svg.append("</svg>")
    with open(out, "w") as f:
        f.write("\n".join(svg) + "\n")


if __name__ == "__main__":
    main()
