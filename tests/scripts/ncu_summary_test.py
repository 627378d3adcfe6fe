#!/usr/bin/env python3
"""scripts/ncu_summary.py on a small CSV of the shape `ncu --csv --page raw` writes: the per-kernel
sums, launch counts, shares and unit conversion must come out as computed by hand."""
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
import ncu_summary  # noqa: E402

CSV = '''"ID","Kernel Name","gpu__time_duration.sum"
"","","nsecond"
"0","void talus::<unnamed>::cull_kernel<double, 1>(talus::ConvexView<double>)","1,000"
"1","void talus::<unnamed>::polytope_kernel<double, 8, 1>(talus::ConvexView<double>)","4,000"
"2","void talus::<unnamed>::cull_kernel<double, 1>(talus::ConvexView<double>)","3,000"
'''


def main():
    with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
        f.write(CSV)
        path = f.name
    try:
        text = ncu_summary.summarise(path)
    finally:
        os.unlink(path)
    lines = text.splitlines()
    # 3 launches, 8000 ns = 0.008 ms; cull: 2 launches, 0.004 ms, 50%; polytope likewise.
    assert lines[0].endswith("3 launches, 0.008 ms (ncu's fixed clocks)"), lines[0]
    # The name column is 70 characters wide, then launches, ms and share.
    rows = {line[:70].strip(): line[70:].split() for line in lines[2:]}
    assert rows["cull_kernel<double, 1>"] == ["2", "0.004", "50.0%"], rows
    assert rows["polytope_kernel<double, 8, 1>"] == ["1", "0.004", "50.0%"], rows
    print("ok")


if __name__ == "__main__":
    main()
