"""The CSV files of the benchmark scripts: one row per run, rewritten after every run so that a
stopped series keeps what it measured (standard library only)."""
import csv


def write_rows(path, fields, rows):
    """Write `rows` (dicts) under the header `fields` to `path`, replacing the file."""
    with open(path, "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)
