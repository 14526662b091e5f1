"""Command-line options of the benchmark scripts (standard library only).

Every script documents its options in its docstring; `arguments(__doc__, values, flags)` checks
sys.argv against them before anything runs, so that `--help` prints the docstring and a misspelt
option stops the script instead of starting a long run with defaults (which would overwrite the
tables in doc/reports/data/).
"""
import sys


def arguments(doc, values, flags=()):
    """Check sys.argv: each of `values` takes one argument, each of `flags` none. Prints doc and
    exits 0 on --help/-h; exits 2 naming the first unknown option or a missing argument."""
    argv = sys.argv[1:]
    if "--help" in argv or "-h" in argv:
        print(doc.strip())
        raise SystemExit(0)
    i = 0
    while i < len(argv):
        name = argv[i]
        if name in values:
            if i + 1 >= len(argv):
                raise SystemExit(f"{sys.argv[0]}: option {name} needs a value (see --help)")
            i += 2
        elif name in flags:
            i += 1
        else:
            raise SystemExit(f"{sys.argv[0]}: unknown option or argument '{name}' (see --help)")


def option(name, default):
    """The value given after `name` on the command line, or `default`."""
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default
