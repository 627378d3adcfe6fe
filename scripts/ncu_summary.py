#!/usr/bin/env python3
"""Sums Nsight Compute's per-launch kernel times (`ncu --metrics gpu__time_duration.sum --csv
--page raw`) per kernel name, one table per CSV given: launches, total ms, share. Used by
scripts/gpu-check's "profile" part; needs only the standard library."""
import csv
import re
import sys


def short_name(name):
    # "void talus::<unnamed>::cull_pair_kernel<double>(...)" -> "cull_pair_kernel<double>"
    name = name.split("(", 1)[0].removeprefix("void ").replace("<unnamed>::", "")
    head, sep, tail = name.partition("<")
    return head.rsplit("::", 1)[-1] + sep + tail


def summarise(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header = next((i for i, r in enumerate(rows) if "Kernel Name" in r), None)
    if header is None:
        return f"{path}: no kernel rows\n"
    names = rows[header]
    k, t = names.index("Kernel Name"), names.index("gpu__time_duration.sum")
    unit = rows[header + 1][t] if header + 1 < len(rows) else ""
    scale = {"ns": 1e-6, "us": 1e-3, "usecond": 1e-3, "ms": 1.0, "msecond": 1.0,
             "nsecond": 1e-6}.get(unit.strip(), 1e-6)
    totals, counts = {}, {}
    for r in rows[header + 2:]:
        if len(r) <= max(k, t) or not r[t]:
            continue
        key = short_name(r[k])
        totals[key] = totals.get(key, 0.0) + float(r[t].replace(",", "")) * scale
        counts[key] = counts.get(key, 0) + 1
    whole = sum(totals.values()) or 1.0
    out = [f"{path}: {sum(counts.values())} launches, {whole:.3f} ms (ncu's fixed clocks)",
           f"{'kernel':70s} {'launches':>8s} {'ms':>9s} {'share':>6s}"]
    for key, ms in sorted(totals.items(), key=lambda kv: -kv[1]):
        out.append(f"{key[:70]:70s} {counts[key]:8d} {ms:9.3f} {100 * ms / whole:5.1f}%")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    print("\n".join(summarise(p) for p in sys.argv[1:]))
