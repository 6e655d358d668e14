#!/usr/bin/env python3
"""Markdown table of A-2.2: our results (CSV of `sim contact --poses ...
--format csv`) side by side with CONTACT's published results
(tables/contact/mbench_a22_contact_reference.csv), mapped to our axes as
tables/contact/README.md says. Usage: a22_table.py OURS.csv [REF.csv]"""
import csv
import sys
from pathlib import Path

ours_path = Path(sys.argv[1])
ref_path = Path(sys.argv[2]) if len(sys.argv) > 2 else (
    Path(__file__).resolve().parent.parent / "tables/contact/mbench_a22_contact_reference.csv")
ours = list(csv.DictReader(l for l in open(ours_path) if not l.startswith("#")))
ref = list(csv.DictReader(open(ref_path)))


def f(v):
    return float(v) if v not in ("", None) else float("nan")


print("| case | wheel | patch | zone | y_tr (mm) ours / CONTACT | angle (rad) ours / CONTACT "
      "| FN (N) ours / CONTACT | Fx (N) ours / CONTACT | Fs (N) ours / CONTACT |")
print("|---|---|---|---|---|---|---|---|---|")
for r in ref:
    side, case = r["wheel"], int(r["case"])
    sign = 1.0 if side == "left" else -1.0
    mine = [o for o in ours if o["side"] == side and int(o["case"]) == case]
    y_ref, a_ref = -f(r["ycp_tr_mm"]), sign * f(r["deltcp_tr_rad"])
    fx_ref, fs_ref, fn_ref = -f(r["fx_n"]), f(r["fs_n"]), f(r["fn_n"])
    for k, o in enumerate(mine):
        def pair(mine_text, ref_text):
            return f"{mine_text} / {ref_text if k == 0 else '—'}"
        cells = [
            pair(f"{f(o['y_tr_mm']):.2f}", f"{y_ref:.2f}"),
            pair(f"{f(o['contact_angle_rad']):+.4f}", f"{a_ref:+.4f}"),
            pair(f"{f(o['fn_n']):.0f}", f"{fn_ref:.0f}"),
            pair(f"{f(o['fx_n']):.0f}", f"{fx_ref:.0f}"),
            pair(f"{f(o['fs_n']):.0f}", f"{fs_ref:.0f}"),
        ]
        print(f"| {case} | {side} | {o['patch']} | {o['zone']} | " + " | ".join(cells) + " |")
