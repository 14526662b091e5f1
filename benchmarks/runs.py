"""Running the program for a benchmark, reading its summary.json, and writing the tables
(standard library only)."""
import csv
import json
import os
import subprocess
import sys
import tempfile


def summary_of_run(exe, prm, settings, np=None, env=None):
    """Runs `exe prm` with the `--set` entries of `settings` into a temporary output folder,
    under `mpirun -np NP --oversubscribe` if np is given, and returns its summary.json. Exits
    naming the command and the end of its stderr if the run wrote none (a run that stops at an
    iteration limit still writes one)."""
    with tempfile.TemporaryDirectory() as out:
        command = (["mpirun", "-np", str(np), "--oversubscribe"] if np else []) + [exe]
        for s in settings + ["Output/Directory=" + out]:
            command += ["--set", s]
        environment = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1",
                           OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", **(env or {}))
        done = subprocess.run(command + [prm], stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True, env=environment)
        path = os.path.join(out, "summary.json")
        if not os.path.exists(path):
            raise SystemExit("%s wrote no summary.json (exit %d): %s"
                             % (" ".join(command + [prm]), done.returncode, done.stderr[-2000:]))
        with open(path) as f:
            return json.load(f)


def write_csv(path, fields, rows):
    """Writes `rows` (dicts) with the columns `fields` to the CSV file `path`."""
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fields)
        writer.writeheader()
        writer.writerows(rows)


def collect_rows(csv_path, fields, measurements):
    """The rows of a benchmark: with --report-only on the command line those of `csv_path`;
    else every row (dict) of every call of `measurements` (callables returning a list of rows),
    the CSV rewritten after each call and its rows printed."""
    if "--report-only" in sys.argv:
        return read_csv(csv_path)
    rows = []
    for measure in measurements:
        new = measure()
        rows += new
        write_csv(csv_path, fields, rows)
        for row in new:
            print(row, flush=True)
    return rows


def read_csv(path):
    """The rows of the CSV file `path` as dicts (values as text)."""
    with open(path) as f:
        return list(csv.DictReader(f))


def write_table(path, lines):
    """Writes the Markdown `lines` to `path` and prints them."""
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
