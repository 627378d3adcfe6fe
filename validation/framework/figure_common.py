"""What the validation cases' figure scripts (validation/<case>/figure.py) share: their command
line `figure.py CHECKS_CSV OUTPUT_PNG [TITLE]`, reading the case's checks.csv (written by
run_validation.cpp) and saving the figure. matplotlib draws off screen (Agg).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402,F401  (the scripts draw with it)


def read_checks(argv, usage):
    """The rows of CHECKS_CSV (argv[1]) as dicts; exits with `usage` when argv is short and with
    a message when the file holds no rows."""
    if len(argv) < 3:
        sys.exit(usage)
    with open(argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{argv[1]}: no rows")
    return rows


def save(fig, argv, title):
    """Titles the figure (TITLE, argv[3], where given) and writes it to OUTPUT_PNG (argv[2])."""
    fig.suptitle(argv[3] if len(argv) > 3 else title, fontsize=10)
    fig.tight_layout()
    fig.savefig(argv[2], dpi=120)
