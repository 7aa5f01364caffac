"""e0a (posterior mean and 95 % interval) against L/d from a campaign table: an SVG.

    python3 docs/campaign_figure.py MANIFEST.csv TABLE.csv OUT.svg

Standard library only. L, d and the support come from each row's beam file
(the top-level `length_nm`, `diameter_nm` and `support` lines of the nominal
beams of data/md/); rows without an e0a (failed records) are listed under the
plot instead. Used for the worked example of docs/campaign.md.
"""

import csv
import re
import sys
from pathlib import Path


def beam_fields(path: Path) -> dict:
    fields = {}
    for line in path.read_text().splitlines():
        m = re.match(r"^(length_nm|diameter_nm|support):\s*([^#\s]+)", line)
        if m:
            fields[m.group(1)] = m.group(2)
    return fields


def main(manifest: str, table: str, out: str) -> None:
    base = Path(manifest).parent
    with open(table, newline="") as f:
        rows = list(csv.DictReader(f))
    points, missing = [], []
    for r in rows:
        if not r["e0a_mean_nm"]:
            missing.append(f"{r['record']}: {r['status']}")
            continue
        b = beam_fields(base / r["beam"])
        ld = float(b["length_nm"]) / float(b["diameter_nm"])
        lo, mean, hi = (float(r[k]) for k in ("e0a_ci95_lo_nm", "e0a_mean_nm", "e0a_ci95_hi_nm"))
        points.append((ld, lo, mean, hi, b["support"], r["record"].split(".")[0]))
    w, h, left, right, top, bottom = 560, 400, 70, 20, 30, 100
    xs = [p[0] for p in points] or [0.0, 1.0]
    x0, x1 = min(xs) - 2, max(xs) + 2
    y1 = max([p[3] for p in points] or [1.0]) * 1.15
    sx = lambda x: left + (x - x0) / (x1 - x0) * (w - left - right)  # noqa: E731
    sy = lambda y: h - bottom - y / y1 * (h - top - bottom)  # noqa: E731
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">']
    svg.append(f'<rect width="{w}" height="{h}" fill="white"/>')
    svg.append(f'<line x1="{left}" y1="{h - bottom}" x2="{w - right}" y2="{h - bottom}" stroke="black"/>')
    svg.append(f'<line x1="{left}" y1="{top}" x2="{left}" y2="{h - bottom}" stroke="black"/>')
    for k in range(6):
        y = y1 * k / 5
        svg.append(f'<text x="{left - 6}" y="{sy(y) + 4:.1f}" text-anchor="end">{y:.3f}</text>')
    for k in range(int(x0) + 1, int(x1) + 1, 2):
        svg.append(f'<text x="{sx(k):.1f}" y="{h - bottom + 16}" text-anchor="middle">{k}</text>')
    svg.append(f'<text x="{(left + w - right) / 2}" y="{h - bottom + 34}" text-anchor="middle">L/d</text>')
    svg.append(f'<text x="16" y="{(top + h - bottom) / 2}" transform="rotate(-90 16 {(top + h - bottom) / 2})" '
               'text-anchor="middle">e0a (nm), posterior mean and 95 % interval</text>')
    colours = {"clamped-clamped": "#1f77b4", "clamped-free": "#d62728"}
    for ld, lo, mean, hi, support, name in points:
        c = colours.get(support, "black")
        svg.append(f'<line x1="{sx(ld):.1f}" y1="{sy(lo):.1f}" x2="{sx(ld):.1f}" y2="{sy(hi):.1f}" stroke="{c}" stroke-width="2"/>')
        svg.append(f'<circle cx="{sx(ld):.1f}" cy="{sy(mean):.1f}" r="4" fill="{c}"/>')
        right_half = sx(ld) > w / 2
        tx, anchor = (sx(ld) - 8, "end") if right_half else (sx(ld) + 8, "start")
        svg.append(f'<text x="{tx:.1f}" y="{sy(mean) + 4:.1f}" text-anchor="{anchor}">{name} ({support})</text>')
    for i, m in enumerate(missing):
        svg.append(f'<text x="{left}" y="{h - 12 - 14 * (len(missing) - 1 - i)}" font-size="10">no e0a: {m}</text>')
    svg.append("</svg>")
    Path(out).write_text("\n".join(svg) + "\n")


if __name__ == "__main__":
    main(*sys.argv[1:4])
